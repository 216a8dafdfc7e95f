-- 011_scan_gaps.sql: the input scan's openings and strays in the run record (schema
-- version 11; written and read by src/catalog/catalog_scan.c, issue 16). A scan as a
-- scanner delivers it is open (the face the part stood on is not seen), has occlusion
-- holes and stray islands; reconstruct closes every opening before it looks for damage
-- (src/mesh/scan_describe.h), so an opening is a scan gap, not a missing section: the
-- run keeps them apart, one row per run in run_scan and one per opening in
-- run_scan_gaps. A run without a row had a closed input (or was recorded before
-- version 11).

-- run_scan: the input read as a scan, one row per run with an open or stray-laden input.
CREATE TABLE run_scan (
    run_id          INTEGER PRIMARY KEY REFERENCES runs (id) ON DELETE CASCADE,  -- the run
    triangles       INTEGER NOT NULL CHECK (triangles >= 0),       -- triangles of the input as read, strays included
    boundary_edges  INTEGER NOT NULL CHECK (boundary_edges >= 0),  -- edges used by one triangle (strays' own excluded)
    gaps            INTEGER NOT NULL CHECK (gaps >= 0),            -- openings (boundary loops): rows in run_scan_gaps
    open_area_mm2   REAL NOT NULL CHECK (open_area_mm2 >= 0),      -- the openings' area, mm^2
    open_share      REAL NOT NULL CHECK (open_share BETWEEN 0 AND 1),  -- open area / (kept surface + open area)
    components      INTEGER NOT NULL CHECK (components >= 0),      -- connected components, strays included
    strays          INTEGER NOT NULL CHECK (strays >= 0),          -- components dropped as strays
    stray_triangles INTEGER NOT NULL CHECK (stray_triangles >= 0), -- their triangles
    stray_area_mm2  REAL NOT NULL CHECK (stray_area_mm2 >= 0)      -- their area, mm^2
) STRICT;

-- run_scan_gaps: one opening of the scan, closed before the reconstruction.
CREATE TABLE run_scan_gaps (
    run_id          INTEGER NOT NULL REFERENCES run_scan (run_id) ON DELETE CASCADE,  -- the run
    gap_index       INTEGER NOT NULL CHECK (gap_index >= 0),       -- 0-based, longest rim first
    edges           INTEGER NOT NULL CHECK (edges >= 0),           -- rim edges
    length_mm       REAL NOT NULL CHECK (length_mm >= 0),          -- rim length, mm
    area_mm2        REAL NOT NULL CHECK (area_mm2 >= 0),           -- area it spans, mm^2
    centre          BLOB NOT NULL CHECK (length(centre) = 24),     -- rim centroid, 3 little-endian doubles, scan frame, mm
    closed_by       TEXT NOT NULL CHECK (closed_by IN ('plane', 'fan', 'open')),  -- how it was closed: in its rim's plane, by a fan from its centroid, or left open
    PRIMARY KEY (run_id, gap_index)                                -- one row per opening of a run
) STRICT, WITHOUT ROWID;

PRAGMA user_version = 11;
