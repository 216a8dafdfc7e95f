-- 004_history_summary.sql: the history summary kept as running totals (schema version
-- 4; read by src/catalog_history.c). Summing 100,000 runs with their sections and
-- advice for every `symrec history --summary` takes about half a second even with the
-- covering indexes of 003; the shop asks that question often and wants it at once.
-- So the figures the summary adds up are kept per part and month of the run's start,
-- updated by triggers on every write to runs, sections, advice and instances, and the
-- summary adds up these few thousand cells instead of the runs. A selection the cells
-- cannot answer exactly (one instance; dates that are not whole months) is still
-- answered from the runs.
--
-- What a cell counts is what the summary query of catalog_history.c reads from a run:
--   * runs, failed (status not 'ok'), the missing volume (sum of the sections'
--     volume_mm3, mm^3);
--   * the outcome: 'advised' = runs with any advice, 'replaced' = runs with an advice
--     whose process begins 'replace' (LIKE, ASCII case ignored); so repair = advised -
--     replaced and none = runs - advised;
--   * per damage class the number of sections (history_class_cells).
-- A run belongs to the cell of its instance's part and substr(started_at, 1, 7), the
-- month 'YYYY-MM'. A date filter on whole months reads the cells only when no run is
-- 'irregular': a start time sorting before the first of its own month ('2024-03' or
-- '2024-03-00...'), which a day-based filter would place differently from its month.
--
-- How the triggers stay exact:
--   * an insert adds to its cell by an upsert written out in its trigger (the path of
--     every recorded run, kept short); every other change goes through two views with
--     INSTEAD OF INSERT triggers (history_cells_add, history_class_cells_add) that add
--     a signed delta to one cell and drop the cell when it no longer counts anything,
--     so a cell exists exactly when a run does;
--   * an insert adds what the new row contributes, a delete subtracts it, an update of
--     a column the figures depend on subtracts the old row and adds the new one (for
--     runs and instances: BEFORE UPDATE subtracts while the row still has its old
--     values, AFTER UPDATE adds);
--   * deleting a run (or an instance) subtracts the whole run (or all the instance's
--     runs) in a BEFORE DELETE trigger, while its sections and advice are still there.
--     SQLite deletes the row before it cascades to the children, so the children's
--     own delete triggers find no run any more and change nothing: nothing is
--     subtracted twice, with foreign keys on or off;
--   * parts carry no trigger: cells are keyed by part id and the summary joins parts
--     for the number and the material, so changing a part's material moves nothing
--     and a part gone takes its cells out of every answer, as it does from the runs.
-- Sums of volumes are floating point: the cells add them in the order they were
-- written, the query over the runs in its own order, so the two agree to rounding
-- (exactly when the volumes are exact binary fractions, as in tests/test_history.c).
-- Not followed: INSERT OR REPLACE over an existing run id with recursive_triggers off
-- (SQLite then deletes the old row without firing delete triggers); symrec never does.

-- The cells are derived data: they carry no CHECK that a delta could trip, so a fault
-- in them can never stop a run from being recorded (a cell whose run count reaches 0
-- is dropped, and the summary reads only cells with runs).

-- history_cells: per part and month, the run figures of the summary.
CREATE TABLE history_cells (
    part_id    INTEGER NOT NULL,                       -- instances.part_id of the runs (no foreign key: derived, kept by the triggers below)
    month      TEXT NOT NULL,                          -- substr(runs.started_at, 1, 7), 'YYYY-MM'
    runs       INTEGER NOT NULL,                       -- runs started that month
    failed     INTEGER NOT NULL,                       -- of them with status 'failed'
    advised    INTEGER NOT NULL,                       -- of them with any advice
    replaced   INTEGER NOT NULL,                       -- of them with an advice whose process is LIKE 'replace%'
    volume_mm3 REAL NOT NULL,                          -- sum of their sections' volume_mm3, mm^3
    irregular  INTEGER NOT NULL,                       -- of them with started_at < month || '-01' (see above)
    PRIMARY KEY (part_id, month)                       -- one cell per part and month
) STRICT, WITHOUT ROWID;

-- history_class_cells: per part, month and damage class, the sections of the runs.
CREATE TABLE history_class_cells (
    part_id  INTEGER NOT NULL,                         -- as history_cells.part_id
    month    TEXT NOT NULL,                            -- as history_cells.month
    class    TEXT NOT NULL,                            -- sections.class
    sections INTEGER NOT NULL,                         -- sections of that class
    PRIMARY KEY (part_id, class, month)                -- one cell per part, class and month (in this order: the summary sums per part and class without sorting)
) STRICT, WITHOUT ROWID;
-- A date range of whole months reads its cells by month, and by part (the keys above)
-- or by material (parts_material, then the keys).
CREATE INDEX history_cells_month ON history_cells (month);
CREATE INDEX history_class_cells_month ON history_class_cells (month);

-- ---- what a run contributes (for the triggers and the backfill) ----

-- history_run_keys: the cell of a run (no row when its instance is gone).
CREATE VIEW history_run_keys AS
SELECT r.id AS run_id, r.instance_id AS instance_id, i.part_id AS part_id,
       substr(r.started_at, 1, 7) AS month
FROM runs r JOIN instances i ON i.id = r.instance_id;

-- history_run_figures: the run figures one run adds to its cell.
CREATE VIEW history_run_figures AS
SELECT r.id AS run_id, r.instance_id AS instance_id, i.part_id AS part_id,
       substr(r.started_at, 1, 7) AS month,
       r.status <> 'ok' AS failed,
       EXISTS (SELECT 1 FROM advice a WHERE a.run_id = r.id) AS advised,
       EXISTS (SELECT 1 FROM advice a WHERE a.run_id = r.id AND a.process LIKE 'replace%')
           AS replaced,
       (SELECT total(s.volume_mm3) FROM sections s WHERE s.run_id = r.id) AS volume_mm3,
       r.started_at < substr(r.started_at, 1, 7) || '-01' AS irregular
FROM runs r JOIN instances i ON i.id = r.instance_id;

-- ---- adding a signed delta to one cell ----

CREATE VIEW history_cells_add AS
SELECT part_id, month, runs, failed, advised, replaced, volume_mm3, irregular
FROM history_cells;

CREATE TRIGGER history_cells_add INSTEAD OF INSERT ON history_cells_add
BEGIN
    INSERT INTO history_cells (part_id, month, runs, failed, advised, replaced, volume_mm3,
                               irregular)
    VALUES (NEW.part_id, NEW.month, NEW.runs, NEW.failed, NEW.advised, NEW.replaced,
            NEW.volume_mm3, NEW.irregular)
    ON CONFLICT (part_id, month) DO UPDATE SET
        runs = runs + excluded.runs, failed = failed + excluded.failed,
        advised = advised + excluded.advised, replaced = replaced + excluded.replaced,
        volume_mm3 = volume_mm3 + excluded.volume_mm3,
        irregular = irregular + excluded.irregular;
    DELETE FROM history_cells WHERE part_id = NEW.part_id AND month = NEW.month AND runs <= 0;
END;

CREATE VIEW history_class_cells_add AS
SELECT part_id, month, class, sections FROM history_class_cells;

CREATE TRIGGER history_class_cells_add INSTEAD OF INSERT ON history_class_cells_add
BEGIN
    INSERT INTO history_class_cells (part_id, month, class, sections)
    VALUES (NEW.part_id, NEW.month, NEW.class, NEW.sections)
    ON CONFLICT (part_id, class, month) DO UPDATE SET sections = sections + excluded.sections;
    DELETE FROM history_class_cells
    WHERE part_id = NEW.part_id AND month = NEW.month AND class = NEW.class AND sections <= 0;
END;

-- ---- runs ----
-- A run's whole contribution (figures and its sections' classes), added after an
-- insert (normally nothing but the run itself: catalog_runs.c writes the run row
-- first, then its sections and advice) and subtracted before a delete.

CREATE TRIGGER history_runs_insert AFTER INSERT ON runs
BEGIN
    INSERT INTO history_cells (part_id, month, runs, failed, advised, replaced, volume_mm3,
                               irregular)
    SELECT part_id, month, 1, failed, advised, replaced, volume_mm3, irregular
    FROM history_run_figures WHERE run_id = NEW.id
    ON CONFLICT (part_id, month) DO UPDATE SET
        runs = runs + 1, failed = failed + excluded.failed,
        advised = advised + excluded.advised, replaced = replaced + excluded.replaced,
        volume_mm3 = volume_mm3 + excluded.volume_mm3,
        irregular = irregular + excluded.irregular;
    INSERT INTO history_class_cells (part_id, month, class, sections)
    SELECT k.part_id, k.month, s.class, count(*)
    FROM history_run_keys k JOIN sections s ON s.run_id = k.run_id
    WHERE k.run_id = NEW.id GROUP BY s.class
    ON CONFLICT (part_id, class, month) DO UPDATE SET sections = sections + excluded.sections;
END;

CREATE TRIGGER history_runs_delete BEFORE DELETE ON runs
BEGIN
    INSERT INTO history_cells_add
    SELECT part_id, month, -1, -failed, -advised, -replaced, -volume_mm3, -irregular
    FROM history_run_figures WHERE run_id = OLD.id;
    INSERT INTO history_class_cells_add
    SELECT k.part_id, k.month, s.class, -count(*)
    FROM history_run_keys k JOIN sections s ON s.run_id = k.run_id
    WHERE k.run_id = OLD.id GROUP BY s.class;
END;

CREATE TRIGGER history_runs_update_old BEFORE UPDATE OF id, instance_id, started_at, status
    ON runs
BEGIN
    INSERT INTO history_cells_add
    SELECT part_id, month, -1, -failed, -advised, -replaced, -volume_mm3, -irregular
    FROM history_run_figures WHERE run_id = OLD.id;
    INSERT INTO history_class_cells_add
    SELECT k.part_id, k.month, s.class, -count(*)
    FROM history_run_keys k JOIN sections s ON s.run_id = k.run_id
    WHERE k.run_id = OLD.id GROUP BY s.class;
END;

CREATE TRIGGER history_runs_update_new AFTER UPDATE OF id, instance_id, started_at, status
    ON runs
BEGIN
    INSERT INTO history_cells_add
    SELECT part_id, month, 1, failed, advised, replaced, volume_mm3, irregular
    FROM history_run_figures WHERE run_id = NEW.id;
    INSERT INTO history_class_cells_add
    SELECT k.part_id, k.month, s.class, count(*)
    FROM history_run_keys k JOIN sections s ON s.run_id = k.run_id
    WHERE k.run_id = NEW.id GROUP BY s.class;
END;

-- ---- instances: all their runs move with them, or go ----

CREATE TRIGGER history_instances_delete BEFORE DELETE ON instances
BEGIN
    INSERT INTO history_cells_add
    SELECT part_id, month, -count(*), -sum(failed), -sum(advised), -sum(replaced),
           -total(volume_mm3), -sum(irregular)
    FROM history_run_figures WHERE instance_id = OLD.id GROUP BY part_id, month;
    INSERT INTO history_class_cells_add
    SELECT k.part_id, k.month, s.class, -count(*)
    FROM history_run_keys k JOIN sections s ON s.run_id = k.run_id
    WHERE k.instance_id = OLD.id GROUP BY k.part_id, k.month, s.class;
END;

CREATE TRIGGER history_instances_update_old BEFORE UPDATE OF id, part_id ON instances
BEGIN
    INSERT INTO history_cells_add
    SELECT part_id, month, -count(*), -sum(failed), -sum(advised), -sum(replaced),
           -total(volume_mm3), -sum(irregular)
    FROM history_run_figures WHERE instance_id = OLD.id GROUP BY part_id, month;
    INSERT INTO history_class_cells_add
    SELECT k.part_id, k.month, s.class, -count(*)
    FROM history_run_keys k JOIN sections s ON s.run_id = k.run_id
    WHERE k.instance_id = OLD.id GROUP BY k.part_id, k.month, s.class;
END;

CREATE TRIGGER history_instances_update_new AFTER UPDATE OF id, part_id ON instances
BEGIN
    INSERT INTO history_cells_add
    SELECT part_id, month, count(*), sum(failed), sum(advised), sum(replaced),
           total(volume_mm3), sum(irregular)
    FROM history_run_figures WHERE instance_id = NEW.id GROUP BY part_id, month;
    INSERT INTO history_class_cells_add
    SELECT k.part_id, k.month, s.class, count(*)
    FROM history_run_keys k JOIN sections s ON s.run_id = k.run_id
    WHERE k.instance_id = NEW.id GROUP BY k.part_id, k.month, s.class;
END;

-- ---- sections: volume and class ----

CREATE TRIGGER history_sections_insert AFTER INSERT ON sections
BEGIN
    INSERT INTO history_cells (part_id, month, runs, failed, advised, replaced, volume_mm3,
                               irregular)
    SELECT part_id, month, 0, 0, 0, 0, NEW.volume_mm3, 0
    FROM history_run_keys WHERE run_id = NEW.run_id
    ON CONFLICT (part_id, month) DO UPDATE SET volume_mm3 = volume_mm3 + excluded.volume_mm3;
    INSERT INTO history_class_cells (part_id, month, class, sections)
    SELECT part_id, month, NEW.class, 1 FROM history_run_keys WHERE run_id = NEW.run_id
    ON CONFLICT (part_id, class, month) DO UPDATE SET sections = sections + 1;
END;

CREATE TRIGGER history_sections_delete AFTER DELETE ON sections
BEGIN
    INSERT INTO history_cells_add
    SELECT part_id, month, 0, 0, 0, 0, -OLD.volume_mm3, 0
    FROM history_run_keys WHERE run_id = OLD.run_id;
    INSERT INTO history_class_cells_add
    SELECT part_id, month, OLD.class, -1 FROM history_run_keys WHERE run_id = OLD.run_id;
END;

CREATE TRIGGER history_sections_update AFTER UPDATE OF run_id, class, volume_mm3 ON sections
BEGIN
    INSERT INTO history_cells_add
    SELECT part_id, month, 0, 0, 0, 0, -OLD.volume_mm3, 0
    FROM history_run_keys WHERE run_id = OLD.run_id;
    INSERT INTO history_class_cells_add
    SELECT part_id, month, OLD.class, -1 FROM history_run_keys WHERE run_id = OLD.run_id;
    INSERT INTO history_cells_add
    SELECT part_id, month, 0, 0, 0, 0, NEW.volume_mm3, 0
    FROM history_run_keys WHERE run_id = NEW.run_id;
    INSERT INTO history_class_cells_add
    SELECT part_id, month, NEW.class, 1 FROM history_run_keys WHERE run_id = NEW.run_id;
END;

-- ---- advice: the outcome ----
-- An advice row changes its run's outcome only when it is the run's first (or last)
-- advice, or its first (or last) 'replace%' advice. An update is the removal of the
-- old row followed by the insertion of the new one; "the advice without this row" is
-- every other row of the run (a.id <> NEW.id).

CREATE TRIGGER history_advice_insert AFTER INSERT ON advice
BEGIN
    INSERT INTO history_cells (part_id, month, runs, failed, advised, replaced, volume_mm3,
                               irregular)
    SELECT part_id, month, 0, 0, adv, rep, 0, 0 FROM (
        SELECT k.part_id, k.month,
               NOT EXISTS (SELECT 1 FROM advice a WHERE a.run_id = NEW.run_id
                           AND a.id <> NEW.id) AS adv,
               NEW.process LIKE 'replace%'
               AND NOT EXISTS (SELECT 1 FROM advice a WHERE a.run_id = NEW.run_id
                               AND a.id <> NEW.id AND a.process LIKE 'replace%') AS rep
        FROM history_run_keys k WHERE k.run_id = NEW.run_id)
    WHERE adv OR rep
    ON CONFLICT (part_id, month) DO UPDATE SET
        advised = advised + excluded.advised, replaced = replaced + excluded.replaced;
END;

CREATE TRIGGER history_advice_delete AFTER DELETE ON advice
BEGIN
    INSERT INTO history_cells_add
    SELECT part_id, month, 0, 0, -adv, -rep, 0, 0 FROM (
        SELECT k.part_id, k.month,
               NOT EXISTS (SELECT 1 FROM advice a WHERE a.run_id = OLD.run_id) AS adv,
               OLD.process LIKE 'replace%'
               AND NOT EXISTS (SELECT 1 FROM advice a WHERE a.run_id = OLD.run_id
                               AND a.process LIKE 'replace%') AS rep
        FROM history_run_keys k WHERE k.run_id = OLD.run_id)
    WHERE adv OR rep;
END;

CREATE TRIGGER history_advice_update AFTER UPDATE OF run_id, process ON advice
BEGIN
    INSERT INTO history_cells_add
    SELECT part_id, month, 0, 0, -adv, -rep, 0, 0 FROM (
        SELECT k.part_id, k.month,
               NOT EXISTS (SELECT 1 FROM advice a WHERE a.run_id = OLD.run_id
                           AND a.id <> NEW.id) AS adv,
               OLD.process LIKE 'replace%'
               AND NOT EXISTS (SELECT 1 FROM advice a WHERE a.run_id = OLD.run_id
                               AND a.id <> NEW.id AND a.process LIKE 'replace%') AS rep
        FROM history_run_keys k WHERE k.run_id = OLD.run_id)
    WHERE adv OR rep;
    INSERT INTO history_cells_add
    SELECT part_id, month, 0, 0, adv, rep, 0, 0 FROM (
        SELECT k.part_id, k.month,
               NOT EXISTS (SELECT 1 FROM advice a WHERE a.run_id = NEW.run_id
                           AND a.id <> NEW.id) AS adv,
               NEW.process LIKE 'replace%'
               AND NOT EXISTS (SELECT 1 FROM advice a WHERE a.run_id = NEW.run_id
                               AND a.id <> NEW.id AND a.process LIKE 'replace%') AS rep
        FROM history_run_keys k WHERE k.run_id = NEW.run_id)
    WHERE adv OR rep;
END;

-- ---- backfill from the runs already recorded ----

INSERT INTO history_cells (part_id, month, runs, failed, advised, replaced, volume_mm3,
                           irregular)
SELECT part_id, month, count(*), sum(failed), sum(advised), sum(replaced), total(volume_mm3),
       sum(irregular)
FROM history_run_figures GROUP BY part_id, month;

INSERT INTO history_class_cells (part_id, month, class, sections)
SELECT k.part_id, k.month, s.class, count(*)
FROM history_run_keys k JOIN sections s ON s.run_id = k.run_id
GROUP BY k.part_id, k.month, s.class;

PRAGMA user_version = 4;
