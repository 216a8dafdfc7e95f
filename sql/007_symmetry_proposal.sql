-- 007_symmetry_proposal.sql: the symmetry `reconstruct --symmetry auto` proposed for a
-- run (schema version 7; written by src/catalog/catalog_runs.c, read by
-- catalog_run_read.c). A run whose symmetry the user gave has no row. The proposal
-- the run then used is also in runs.symmetry/order/shift_mm as for any run; this row
-- says it was proposed, how sure the fit was and how every kind scored
-- (src/align/symmetry_fit.h): the columns for queries ("runs where the fit was
-- ambiguous"), the whole fit as one JSON object (src/run/run_symfit.h) for display.
CREATE TABLE run_symmetry_fit (
    run_id      INTEGER PRIMARY KEY REFERENCES runs (id) ON DELETE CASCADE,  -- the run
    kind        TEXT NOT NULL CHECK (kind IN ('axial', 'mirror', 'glide')),  -- proposed
    order_n     INTEGER NOT NULL DEFAULT 0 CHECK (order_n >= 0),  -- axial: 0 = continuous
    shift_mm    REAL NOT NULL DEFAULT 0 CHECK (shift_mm >= 0),    -- glide: the shift found
    confidence  REAL NOT NULL CHECK (confidence >= 0 AND confidence <= 1),  -- 0..1
    ambiguous   INTEGER NOT NULL CHECK (ambiguous IN (0, 1)),     -- 1: alternative fits as well
    alternative TEXT CHECK (alternative IN ('axial', 'mirror', 'glide')),  -- kind, or NULL
    fit_json    TEXT NOT NULL CHECK (json_valid(fit_json))        -- the whole fit
);

PRAGMA user_version = 7;
