-- 008_nominal.sql: the nominal model's second opinion on a run (schema version 8;
-- written by src/catalog/catalog_nominal.c, issue 19 item 3). When the instance's part
-- has an intact mesh, reconstruct registers it to the scan and takes registered intact
-- - scan as the nominal's missing material (src/nominal.h); a run keeps the figures:
-- one row per run in run_nominal, one per symmetry section in run_nominal_sections,
-- one per kept piece of the nominal in run_nominal_pieces. No meshes: the registered
-- intact mesh is the part's mesh under the recorded transform. A run without a row
-- had no nominal (no intact mesh, --no-nominal, or recorded before version 8).

-- run_nominal: the run-level figures of the comparison.
CREATE TABLE run_nominal (
    run_id          INTEGER PRIMARY KEY REFERENCES runs (id) ON DELETE CASCADE,  -- the run
    reference       TEXT NOT NULL CHECK (reference IN ('symmetry', 'nominal')),  -- what the run's restoration is
    transform       BLOB NOT NULL CHECK (length(transform) = 96),  -- intact -> scan frame, 12 little-endian doubles, 3x4 row-major
    coverage        REAL NOT NULL CHECK (coverage BETWEEN 0 AND 1),  -- share of the intact's samples within tol_mm of the scan
    rms_mm          REAL NOT NULL CHECK (rms_mm >= 0),            -- RMS distance of those samples, mm
    tol_mm          REAL NOT NULL CHECK (tol_mm >= 0),            -- the registration tolerance, mm
    nominal_mm3     REAL NOT NULL CHECK (nominal_mm3 >= 0),       -- the nominal's missing volume (kept pieces), mm^3
    symmetry_mm3    REAL NOT NULL CHECK (symmetry_mm3 >= 0),      -- the symmetry's (sum of the sections), mm^3
    diff_mm3        REAL NOT NULL,                                -- nominal - symmetry, mm^3
    diff_pct        REAL NOT NULL,                                -- diff as % of the nominal (of the symmetry when the nominal is 0)
    sliver_mm       REAL NOT NULL CHECK (sliver_mm >= 0),         -- pieces thinner than this were slivers, mm
    slivers         INTEGER NOT NULL CHECK (slivers >= 0),        -- pieces dropped as slivers or under min_volume_mm3
    sliver_mm3      REAL NOT NULL CHECK (sliver_mm3 >= 0),        -- their volume, mm^3
    min_volume_mm3  REAL NOT NULL CHECK (min_volume_mm3 >= 0),    -- smallest piece or share counted, mm^3
    scan_outside_mm3 REAL NOT NULL CHECK (scan_outside_mm3 >= 0), -- scan material outside the registered nominal, mm^3
    scan_outside_limit_mm3 REAL NOT NULL CHECK (scan_outside_limit_mm3 >= 0),  -- the scan's area x tol_mm, mm^3
    poor            INTEGER NOT NULL CHECK (poor IN (0, 1)),      -- 1: the nominal does not fit the scan
    note            TEXT NOT NULL,                                -- why it does not ('' when it fits)
    seconds         REAL NOT NULL CHECK (seconds >= 0)            -- time the comparison took, s
) STRICT;

-- run_nominal_sections: each symmetry section of the run beside the nominal.
CREATE TABLE run_nominal_sections (
    run_id          INTEGER NOT NULL REFERENCES run_nominal (run_id) ON DELETE CASCADE,  -- the run
    section_index   INTEGER NOT NULL CHECK (section_index >= 0),  -- sections.section_index
    symmetry_mm3    REAL NOT NULL CHECK (symmetry_mm3 >= 0),      -- the section's volume, mm^3
    nominal_mm3     REAL NOT NULL,                                -- the nominal's volume near its patch, mm^3
    diff_mm3        REAL NOT NULL,                                -- nominal - symmetry, mm^3
    diff_pct        REAL NOT NULL,                                -- as run_nominal.diff_pct
    deviation_mean_mm REAL,                                       -- mean distance of the patch's surface from the nominal's, mm; NULL = no nominal piece
    deviation_max_mm  REAL,                                       -- the largest, mm; NULL = no nominal piece
    pieces          INTEGER NOT NULL CHECK (pieces >= 0),         -- nominal pieces with a share here (0 = only the symmetry sees it)
    PRIMARY KEY (run_id, section_index)                          -- one row per section of a run
) STRICT, WITHOUT ROWID;

-- run_nominal_pieces: the nominal's kept pieces of missing material.
CREATE TABLE run_nominal_pieces (
    run_id          INTEGER NOT NULL REFERENCES run_nominal (run_id) ON DELETE CASCADE,  -- the run
    piece_index     INTEGER NOT NULL CHECK (piece_index >= 0),    -- 0 = the largest
    volume_mm3      REAL NOT NULL,                                -- its volume, mm^3
    thickness_mm    REAL NOT NULL,                                -- 2 x volume / area, mm
    section_index   INTEGER,                                      -- the section with the largest share; NULL = none
    outside_mm3     REAL NOT NULL,                                -- its share near no section (only the nominal sees it), mm^3
    centroid        BLOB NOT NULL CHECK (length(centroid) = 24),  -- volume centroid of that share (of the piece when small), 3 little-endian doubles, scan frame, mm
    PRIMARY KEY (run_id, piece_index)                            -- one row per piece of a run
) STRICT, WITHOUT ROWID;

PRAGMA user_version = 8;
