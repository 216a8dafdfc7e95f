-- 009_inspection.sql: inspections of repaired parts against their run's restoration
-- (schema version 9; written and read by src/catalog/catalog_inspect.c, issue 20). The
-- shop scans a part after repair and `symrec inspect` measures it against the run's
-- restored mesh (src/inspect/inspect.h): one row per inspection in inspections, one
-- per section of the run in inspection_sections, the scan stored like every mesh. A
-- run's outcome follows its latest inspection (run_latest_inspection); the history
-- summary counts runs by that verdict per part and month in history_verdict_cells,
-- kept by triggers as sql/004_history_summary.sql keeps its cells (same rules: an
-- insert adds, a delete subtracts, an update subtracts the old and adds the new,
-- deleting a run or an instance subtracts while its rows are still there). An
-- inspection is a measurement and is not changed: a new one is added instead.

-- inspections: one measurement of a repaired part against run run_id's restoration.
CREATE TABLE inspections (
    id                 INTEGER PRIMARY KEY,                             -- row id
    run_id             INTEGER NOT NULL REFERENCES runs (id) ON DELETE CASCADE,  -- the run whose restored mesh is the reference
    scan_mesh_id       INTEGER REFERENCES meshes (id) ON DELETE SET NULL,  -- the scan after repair, as read (its own frame); NULL = not kept
    transform          BLOB NOT NULL CHECK (length(transform) = 96),    -- scan -> restored model frame, 12 little-endian doubles, 3x4 row-major
    registered         INTEGER NOT NULL CHECK (registered IN (0, 1)),   -- 1: the scan was registered; 0: taken as it lay
    coverage           REAL NOT NULL CHECK (coverage BETWEEN 0 AND 1),  -- share of the scan within reg_tol_mm of the model outside the sections
    reg_tol_mm         REAL NOT NULL CHECK (reg_tol_mm >= 0),           -- that tolerance, mm
    allowance_mm       REAL NOT NULL CHECK (allowance_mm >= 0),         -- machining allowance used, mm
    tolerance_mm       REAL NOT NULL CHECK (tolerance_mm > 0),          -- deviation tolerance used, mm
    volumes_exact      INTEGER NOT NULL CHECK (volumes_exact IN (0, 1)),  -- 1: volumes by booleans; 0: estimated from samples
    outside_samples    INTEGER NOT NULL CHECK (outside_samples >= 0),   -- scan samples outside every section
    outside_share      REAL NOT NULL CHECK (outside_share BETWEEN 0 AND 1),  -- of them, the share beyond the tolerance
    outside_max_mm     REAL NOT NULL CHECK (outside_max_mm >= 0),       -- largest |deviation| outside the sections, mm
    outside_rms_mm     REAL NOT NULL CHECK (outside_rms_mm >= 0),       -- RMS deviation outside the sections, mm
    outside_overbuild_mm3 REAL NOT NULL,                                -- scan material above the model away from the sections, mm^3
    verdict            TEXT NOT NULL CHECK (verdict IN ('pass', 'machine', 'rework')),  -- overall verdict
    reasons            TEXT NOT NULL,                                   -- why, one line
    software_version   TEXT NOT NULL,                                   -- symrec version that measured
    inspected_at       TEXT NOT NULL                                    -- when (UTC, ISO 8601)
) STRICT;
CREATE INDEX inspections_run ON inspections (run_id, inspected_at, id);  -- a run's inspections, latest last
CREATE INDEX inspections_scan_mesh ON inspections (scan_mesh_id);        -- foreign key

-- inspection_sections: the figures of each section of the run in one inspection.
CREATE TABLE inspection_sections (
    inspection_id      INTEGER NOT NULL REFERENCES inspections (id) ON DELETE CASCADE,  -- the inspection
    section_index      INTEGER NOT NULL CHECK (section_index >= 0),     -- sections.section_index of the run
    patch_mm3          REAL NOT NULL CHECK (patch_mm3 >= 0),            -- the section's missing volume, mm^3
    underfill_mm3      REAL NOT NULL,                                   -- restored material the repair did not reach, mm^3
    underfill_depth_mm REAL NOT NULL CHECK (underfill_depth_mm >= 0),   -- largest depth below the restored surface, mm
    overbuild_mm3      REAL NOT NULL,                                   -- material above the restored surface, mm^3
    stock_min_mm       REAL NOT NULL,                                   -- stock thickness over the samples above the tolerance: min, mm
    stock_max_mm       REAL NOT NULL,                                   -- max, mm
    stock_mean_mm      REAL NOT NULL,                                   -- mean, mm
    stock_share        REAL NOT NULL CHECK (stock_share BETWEEN 0 AND 1),  -- share of the section's samples above the tolerance
    under_share        REAL NOT NULL CHECK (under_share BETWEEN 0 AND 1),  -- share deeper than the tolerance
    dev_mean_mm        REAL NOT NULL,                                   -- signed deviation of its samples: mean, mm
    dev_rms_mm         REAL NOT NULL CHECK (dev_rms_mm >= 0),           -- RMS, mm
    dev_min_mm         REAL NOT NULL,                                   -- min, mm
    dev_max_mm         REAL NOT NULL,                                   -- max, mm
    samples            INTEGER NOT NULL CHECK (samples >= 0),           -- scan samples over the section
    verdict            TEXT NOT NULL CHECK (verdict IN ('pass', 'machine', 'rework')),  -- the section's verdict
    reasons            TEXT NOT NULL,                                   -- why, one line
    PRIMARY KEY (inspection_id, section_index)         -- one row per section and inspection
) STRICT, WITHOUT ROWID;

CREATE TRIGGER inspections_immutable BEFORE UPDATE ON inspections
BEGIN
    SELECT RAISE(ABORT, 'an inspection is not changed: add a new one');
END;

-- run_latest_inspection: each inspected run's latest inspection (by time, then id).
CREATE VIEW run_latest_inspection AS
SELECT v.* FROM inspections v
WHERE v.id = (SELECT w.id FROM inspections w WHERE w.run_id = v.run_id
              ORDER BY w.inspected_at DESC, w.id DESC LIMIT 1);

-- history_verdict_cells: per part, month and verdict, the runs whose latest inspection
-- gave that verdict (cells as history_cells of 004: derived, no foreign keys).
CREATE TABLE history_verdict_cells (
    part_id  INTEGER NOT NULL,                         -- instances.part_id of the runs
    month    TEXT NOT NULL,                            -- substr(runs.started_at, 1, 7)
    verdict  TEXT NOT NULL,                            -- the latest inspection's verdict
    runs     INTEGER NOT NULL,                         -- runs with that verdict
    PRIMARY KEY (part_id, verdict, month)              -- one cell per part, verdict and month
) STRICT, WITHOUT ROWID;
CREATE INDEX history_verdict_cells_month ON history_verdict_cells (month);

-- history_run_verdicts: the cell and verdict of each inspected run.
CREATE VIEW history_run_verdicts AS
SELECT k.run_id AS run_id, k.instance_id AS instance_id, k.part_id AS part_id,
       k.month AS month, v.verdict AS verdict
FROM history_run_keys k JOIN run_latest_inspection v ON v.run_id = k.run_id;

CREATE VIEW history_verdict_cells_add AS
SELECT part_id, month, verdict, runs FROM history_verdict_cells;

CREATE TRIGGER history_verdict_cells_add INSTEAD OF INSERT ON history_verdict_cells_add
BEGIN
    INSERT INTO history_verdict_cells (part_id, month, verdict, runs)
    VALUES (NEW.part_id, NEW.month, NEW.verdict, NEW.runs)
    ON CONFLICT (part_id, verdict, month) DO UPDATE SET runs = runs + excluded.runs;
    DELETE FROM history_verdict_cells
    WHERE part_id = NEW.part_id AND month = NEW.month AND verdict = NEW.verdict AND runs <= 0;
END;

-- ---- inspections: the run's verdict before and after ----

CREATE TRIGGER history_inspections_insert AFTER INSERT ON inspections
BEGIN
    INSERT INTO history_verdict_cells_add
    SELECT k.part_id, k.month, b.verdict, -1
    FROM history_run_keys k,
         (SELECT verdict FROM inspections WHERE run_id = NEW.run_id AND id <> NEW.id
          ORDER BY inspected_at DESC, id DESC LIMIT 1) b
    WHERE k.run_id = NEW.run_id;
    INSERT INTO history_verdict_cells_add
    SELECT part_id, month, verdict, 1 FROM history_run_verdicts WHERE run_id = NEW.run_id;
END;

CREATE TRIGGER history_inspections_delete AFTER DELETE ON inspections
BEGIN
    INSERT INTO history_verdict_cells_add
    SELECT k.part_id, k.month, b.verdict, -1
    FROM history_run_keys k,
         (SELECT verdict FROM (SELECT verdict, inspected_at, id FROM inspections
                               WHERE run_id = OLD.run_id
                               UNION ALL SELECT OLD.verdict, OLD.inspected_at, OLD.id)
          ORDER BY inspected_at DESC, id DESC LIMIT 1) b
    WHERE k.run_id = OLD.run_id;
    INSERT INTO history_verdict_cells_add
    SELECT part_id, month, verdict, 1 FROM history_run_verdicts WHERE run_id = OLD.run_id;
END;

-- ---- runs and instances: their verdicts move with them, or go ----

CREATE TRIGGER history_verdict_runs_delete BEFORE DELETE ON runs
BEGIN
    INSERT INTO history_verdict_cells_add
    SELECT part_id, month, verdict, -1 FROM history_run_verdicts WHERE run_id = OLD.id;
END;

CREATE TRIGGER history_verdict_runs_update_old BEFORE UPDATE OF id, instance_id, started_at
    ON runs
BEGIN
    INSERT INTO history_verdict_cells_add
    SELECT part_id, month, verdict, -1 FROM history_run_verdicts WHERE run_id = OLD.id;
END;

CREATE TRIGGER history_verdict_runs_update_new AFTER UPDATE OF id, instance_id, started_at
    ON runs
BEGIN
    INSERT INTO history_verdict_cells_add
    SELECT part_id, month, verdict, 1 FROM history_run_verdicts WHERE run_id = NEW.id;
END;

CREATE TRIGGER history_verdict_instances_delete BEFORE DELETE ON instances
BEGIN
    INSERT INTO history_verdict_cells_add
    SELECT part_id, month, verdict, -count(*) FROM history_run_verdicts
    WHERE instance_id = OLD.id GROUP BY part_id, month, verdict;
END;

CREATE TRIGGER history_verdict_instances_update_old BEFORE UPDATE OF id, part_id ON instances
BEGIN
    INSERT INTO history_verdict_cells_add
    SELECT part_id, month, verdict, -count(*) FROM history_run_verdicts
    WHERE instance_id = OLD.id GROUP BY part_id, month, verdict;
END;

CREATE TRIGGER history_verdict_instances_update_new AFTER UPDATE OF id, part_id ON instances
BEGIN
    INSERT INTO history_verdict_cells_add
    SELECT part_id, month, verdict, count(*) FROM history_run_verdicts
    WHERE instance_id = NEW.id GROUP BY part_id, month, verdict;
END;

PRAGMA user_version = 9;
