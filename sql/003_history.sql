-- 003_history.sql: indexes for history queries over the run record (schema version 3;
-- src/catalog_history.c). A history row per run needs, besides the run itself, its
-- section count, missing volume and damage classes, and the processes advised; the
-- summaries group those by part, class, outcome and month. With 100,000 runs these
-- per-run look-ups must never touch the tables' rows, so each gets a covering index:
--
--   * sections_history: a run's sections with class and volume, so count(*),
--     sum(volume_mm3) and the classes of one run are one index range read (the
--     UNIQUE (run_id, section_index) index would need a table look-up per section);
--   * advice_history: a run's advised processes, one index range read (advice_run
--     holds only run_id);
--   * runs_history_instance: a part's or material's runs come through its instances
--     (instances_part, then this index), with the start time and status read from the
--     index for the date filter, the ordering and the outcome counts;
--   * runs_history_started: a date range of runs, with the instance and status at hand
--     (runs_started holds only started_at).
--
-- Queries filter dates on runs.started_at (UTC text, sorts as time), parts through
-- instances.part_id (instances_part of 001) and materials through parts.material_id
-- (parts_material of 001).
CREATE INDEX sections_history ON sections (run_id, class, volume_mm3);
CREATE INDEX advice_history ON advice (run_id, process);
CREATE INDEX runs_history_instance ON runs (instance_id, started_at, status);
CREATE INDEX runs_history_started ON runs (started_at, instance_id, status);

PRAGMA user_version = 3;
