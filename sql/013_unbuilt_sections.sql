-- 013_unbuilt_sections.sql: the sections a run found missing but could build no patch
-- for (schema version 13; written by src/catalog/catalog_runs.c, read by
-- catalog_run_read.c, issue 16). The image method's vote can find a region missing whose
-- images of the scan clip to nothing closed (a scan not closed there); such a section is
-- not restored and not among the run's sections, and a history that showed the run as
-- "nothing to repair" would mislead. One row per run that had any; none = every section
-- found was built (and for every run recorded before version 13).
CREATE TABLE run_unbuilt (
    run_id     INTEGER PRIMARY KEY REFERENCES runs (id) ON DELETE CASCADE,  -- the run
    sections   INTEGER NOT NULL CHECK (sections >= 1),    -- sections found missing that gave no closed patch
    volume_mm3 REAL NOT NULL CHECK (volume_mm3 >= 0)      -- their volume by the vote's voxels, mm^3
) STRICT;

PRAGMA user_version = 13;
