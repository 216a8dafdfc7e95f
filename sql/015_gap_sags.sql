-- 015_gap_sags.sql: what a run restored behind the fills of its scan's gaps (schema
-- version 15; written and read by src/catalog/catalog_scan.c, issue 16). An opening is
-- closed flat; where the surface the scanner did not see was curved or ran over an
-- edge, the image method finds the lens between the fill and that surface missing. It
-- is restored with the part, but it is the scan's gap, not damage: no section, no
-- advice (src/reconstruct_gaps.c). The run keeps how many and how much, apart from its
-- sections. Runs recorded before version 15 have 0.
ALTER TABLE run_scan ADD COLUMN sags INTEGER NOT NULL DEFAULT 0
    CHECK (sags >= 0);                                            -- lenses restored behind gap fills, not sections
ALTER TABLE run_scan ADD COLUMN sag_mm3 REAL NOT NULL DEFAULT 0
    CHECK (sag_mm3 >= 0);                                         -- their volume, mm^3

PRAGMA user_version = 15;
