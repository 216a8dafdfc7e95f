-- 010_nominal_method.sql: how a run's nominal missing material was measured (schema
-- version 10; written by src/catalog/catalog_nominal.c). sr_nominal_compare measures
-- registered intact - scan either by one exact CGAL difference (pieces as meshes) or,
-- by default and whenever the exact difference refuses the scan (a noisy scan crossing
-- itself), by cells of a grid (exact volumes per cell, no meshes). The two can differ
-- by a fraction of a per cent, so a run keeps which one it used. Runs recorded before
-- version 10 have NULL: not known.
ALTER TABLE run_nominal ADD COLUMN method TEXT
    CHECK (method IS NULL OR method IN ('exact', 'cells'));       -- how nominal_mm3 was measured; NULL = recorded before version 10
ALTER TABLE run_nominal ADD COLUMN cell_mm REAL
    CHECK (cell_mm IS NULL OR cell_mm > 0);                       -- the cells' size when method = 'cells', mm; else NULL
ALTER TABLE run_nominal ADD COLUMN exact_note TEXT NOT NULL DEFAULT '';  -- why the exact difference was refused ('' when not asked or when it was not)

PRAGMA user_version = 10;
