-- 001_init.sql: the first schema of a symrec catalogue (schema version 1).
--
-- A catalogue holds the shop's parts (models) with their intact meshes, the damaged
-- instances of those parts with their scans, the symmetry chosen for each, named
-- parameter sets, and the record of every reconstruction: runs, their per-layer
-- outlines, the missing sections found, repair rules and the advice they gave.
--
-- Applied by src/catalog.c inside one BEGIN IMMEDIATE transaction; the file ends by
-- setting user_version to its own number, which catalog.c checks before COMMIT.
-- Conventions:
--   * every table is STRICT (SQLite >= 3.37): a value of the wrong type is refused;
--   * ids are INTEGER PRIMARY KEY (the rowid);
--   * lengths of text fields are checked in bytes (length(CAST(x AS BLOB))) because
--     the C structs that read them back have fixed-size byte arrays;
--   * times are UTC ISO 8601 text, 'YYYY-MM-DDTHH:MM:SSZ', dates 'YYYY-MM-DD', so they
--     sort and compare as text;
--   * lengths in millimetres, areas mm^2, volumes mm^3, angles degrees;
--   * ON DELETE: history is never dropped by accident. Deleting a part, a mesh or a
--     material still in use is refused (RESTRICT); what belongs to one run or one
--     instance (layers, sections, advice, symmetry overrides) goes with it (CASCADE);
--     a link to something optional (a restored mesh, a rule) is cleared (SET NULL).
--   * every foreign key column is indexed (deletes of the parent and joins).

-- 'SYMR': marks the file as a symrec catalogue (SR_CATALOG_APP_ID in catalog.h).
PRAGMA application_id = 0x53594d52;

-- materials: what parts are made of; created by name the first time a part names one.
-- Later migrations add process limits (e.g. which repair processes suit a material).
CREATE TABLE materials (
    id            INTEGER PRIMARY KEY,                 -- row id
    name          TEXT NOT NULL UNIQUE COLLATE NOCASE  -- e.g. '42CrMo4'; unique ignoring ASCII case
                  CHECK (length(CAST(name AS BLOB)) BETWEEN 1 AND 63),
    density_g_cm3 REAL                                 -- density in g/cm^3; NULL = not known yet
                  CHECK (density_g_cm3 IS NULL OR density_g_cm3 > 0),
    notes         TEXT NOT NULL DEFAULT '',            -- free text: standard, supplier, heat treatment
    created_at    TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))  -- when first named (UTC)
) STRICT;

-- meshes: every triangle mesh the catalogue holds (intact models, damaged scans,
-- restored parts, patches), with the figures a listing shows, so listings never read
-- the geometry. The blob is the last column: SQLite stores a row's columns in order,
-- so reading the figures does not touch the blob's overflow pages.
CREATE TABLE meshes (
    id             INTEGER PRIMARY KEY,                -- row id
    vertex_count   INTEGER NOT NULL CHECK (vertex_count BETWEEN 3 AND 4294967295),  -- V, vertices in data
    tri_count      INTEGER NOT NULL CHECK (tri_count BETWEEN 1 AND 4294967295),     -- T, triangles in data
    volume_mm3     REAL NOT NULL,                      -- enclosed signed volume (meaningful when closed)
    area_mm2       REAL NOT NULL CHECK (area_mm2 >= 0),  -- total surface area
    bbox_min_x     REAL NOT NULL,                      -- axis-aligned bounding box, lower x
    bbox_min_y     REAL NOT NULL,                      -- lower y
    bbox_min_z     REAL NOT NULL,                      -- lower z
    bbox_max_x     REAL NOT NULL CHECK (bbox_max_x >= bbox_min_x),  -- upper x
    bbox_max_y     REAL NOT NULL CHECK (bbox_max_y >= bbox_min_y),  -- upper y
    bbox_max_z     REAL NOT NULL CHECK (bbox_max_z >= bbox_min_z),  -- upper z
    closed         INTEGER NOT NULL CHECK (closed IN (0, 1)),  -- 1 = every edge shared by two triangles, consistently oriented
    source_file    TEXT,                               -- file the mesh was read from; NULL if built in memory
    format_version INTEGER NOT NULL CHECK (format_version >= 1),  -- version of the blob format (src/mesh_blob.h)
    created_at     TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now')),  -- when stored (UTC)
    data           BLOB NOT NULL                       -- the mesh, src/mesh_blob.h format; version 1 is exactly 24 + 24 V + 12 T bytes
                   CHECK (format_version <> 1 OR length(data) = 24 + 24 * vertex_count + 12 * tri_count)
) STRICT;

-- parts: the shop's parts (models), each with its intact model mesh when one is known.
CREATE TABLE parts (
    id          INTEGER PRIMARY KEY,                   -- row id; also accepted where a part number is
    number      TEXT NOT NULL UNIQUE COLLATE NOCASE    -- the shop's part number, unique ignoring ASCII case
                CHECK (length(CAST(number AS BLOB)) BETWEEN 1 AND 63),
    name        TEXT NOT NULL                          -- descriptive name, e.g. 'drive shaft'
                CHECK (length(CAST(name AS BLOB)) BETWEEN 1 AND 127),
    material_id INTEGER REFERENCES materials (id) ON DELETE RESTRICT,  -- what it is made of; NULL = not given
    notes       TEXT NOT NULL DEFAULT ''               -- free text
                CHECK (length(CAST(notes AS BLOB)) <= 511),
    mesh_id     INTEGER REFERENCES meshes (id) ON DELETE RESTRICT,     -- intact model mesh; NULL = none yet
    created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))  -- when added (UTC)
) STRICT;
CREATE INDEX parts_material ON parts (material_id);  -- history and listings by material
CREATE INDEX parts_mesh ON parts (mesh_id);          -- foreign key

-- instances: damaged pieces of a part as received for repair, each with its scan.
CREATE TABLE instances (
    id          INTEGER PRIMARY KEY,                   -- row id, the instance's number in the CLI
    part_id     INTEGER NOT NULL REFERENCES parts (id) ON DELETE RESTRICT,  -- which part this is a piece of
    serial      TEXT                                   -- the piece's serial number; NULL = unknown
                CHECK (serial IS NULL OR length(CAST(serial AS BLOB)) BETWEEN 1 AND 63),
    received    TEXT                                   -- date received 'YYYY-MM-DD'; NULL = unknown
                CHECK (received IS NULL OR (received GLOB '[0-9][0-9][0-9][0-9]-[0-9][0-9]-[0-9][0-9]'
                                            AND date(received) IS NOT NULL)),
    notes       TEXT NOT NULL DEFAULT ''               -- free text: what is broken, where from
                CHECK (length(CAST(notes AS BLOB)) <= 511),
    mesh_id     INTEGER NOT NULL REFERENCES meshes (id) ON DELETE RESTRICT,  -- the damaged scan
    created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))  -- when added (UTC)
) STRICT;
CREATE INDEX instances_part ON instances (part_id, received);  -- instances of a part, by date
CREATE INDEX instances_received ON instances (received);       -- history by date
CREATE INDEX instances_serial ON instances (serial);           -- look-up by serial
CREATE INDEX instances_mesh ON instances (mesh_id);            -- foreign key

-- symmetries: the symmetry a part is restored by, set on the part or overridden on one
-- instance (exactly one of part_id, instance_id). The axis/plane columns override the
-- found alignment: all NULL = find it by search (paper Alg. 3).
CREATE TABLE symmetries (
    id          INTEGER PRIMARY KEY,                   -- row id
    part_id     INTEGER UNIQUE REFERENCES parts (id) ON DELETE CASCADE,      -- the part, or NULL
    instance_id INTEGER UNIQUE REFERENCES instances (id) ON DELETE CASCADE,  -- the instance, or NULL
    kind        TEXT NOT NULL CHECK (kind IN ('axial', 'mirror', 'glide')),   -- symmetry kind (sr_sym_kind)
    order_n     INTEGER NOT NULL DEFAULT 0             -- axial n-fold order; 0 = continuous
                CHECK (order_n = 0 OR order_n BETWEEN 2 AND 360),
    shift_mm    REAL NOT NULL DEFAULT 0 CHECK (shift_mm >= 0),  -- glide: shift along the plane; 0 = find by search
    origin_x    REAL,                                  -- override: a point on the axis or plane, x; NULL = search
    origin_y    REAL,                                  -- y
    origin_z    REAL,                                  -- z
    dir_x       REAL,                                  -- override: axis direction (axial) or plane normal (mirror, glide), x
    dir_y       REAL,                                  -- y
    dir_z       REAL,                                  -- z
    notes       TEXT NOT NULL DEFAULT '',              -- free text: why this symmetry
    updated_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now')),  -- when last set (UTC)
    CHECK ((part_id IS NULL) <> (instance_id IS NULL)),
    CHECK ((origin_x IS NULL) = (origin_y IS NULL) AND (origin_y IS NULL) = (origin_z IS NULL)),
    CHECK ((dir_x IS NULL) = (dir_y IS NULL) AND (dir_y IS NULL) = (dir_z IS NULL)),
    CHECK (dir_x IS NULL OR dir_x * dir_x + dir_y * dir_y + dir_z * dir_z > 0)
) STRICT;

-- parameter_sets: named settings of the reconstruction (paper section 4), picked by
-- name at run time; a run copies the values it used, so editing a set never rewrites
-- history.
CREATE TABLE parameter_sets (
    id             INTEGER PRIMARY KEY,                -- row id
    name           TEXT NOT NULL UNIQUE COLLATE NOCASE  -- e.g. 'default'; unique ignoring ASCII case
                   CHECK (length(CAST(name AS BLOB)) BETWEEN 1 AND 63),
    layers         INTEGER NOT NULL CHECK (layers BETWEEN 1 AND 100000),     -- N_layers, slices along z
    sectors        INTEGER NOT NULL CHECK (sectors BETWEEN 3 AND 100000),    -- N_sectors, polar sectors per layer
    gamma_axis     REAL NOT NULL CHECK (gamma_axis > 0 AND gamma_axis <= 1),    -- Alg. 4: sector damaged if D_j < gamma_axis * D_max
    gamma_plane    REAL NOT NULL CHECK (gamma_plane > 0 AND gamma_plane <= 1),  -- Alg. 5: pair damaged if min/max < gamma_plane
    delta_d        REAL NOT NULL CHECK (delta_d > 0 AND delta_d <= 1),          -- Alg. 3: layer symmetric if max |D_k - D_avg| / D_avg < delta_d
    min_depth_mm   REAL NOT NULL CHECK (min_depth_mm >= 0),    -- smallest depth reported as a missing section
    min_volume_mm3 REAL NOT NULL CHECK (min_volume_mm3 >= 0),  -- smallest volume reported as a missing section
    notes          TEXT NOT NULL DEFAULT ''            -- where the values come from
                   CHECK (length(CAST(notes AS BLOB)) <= 255),
    created_at     TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))  -- when added (UTC)
) STRICT;

-- The paper's three settings of (N_sectors, N_layers) from its Table 2. The paper gives
-- no values for the thresholds: those below are symrec's starting choice.
INSERT INTO parameter_sets (name, layers, sectors, gamma_axis, gamma_plane, delta_d,
                            min_depth_mm, min_volume_mm3, notes) VALUES
    ('coarse', 80, 60, 0.95, 0.95, 0.05, 0.1, 1.0,
     'sectors/layers 60/80: coarsest setting of the paper''s Table 2; thresholds as default'),
    ('medium', 160, 120, 0.95, 0.95, 0.05, 0.1, 1.0,
     'sectors/layers 120/160: middle setting of the paper''s Table 2; thresholds as default'),
    ('default', 320, 240, 0.95, 0.95, 0.05, 0.1, 1.0,
     'sectors/layers 240/320: finest setting of the paper''s Table 2; gamma, delta_d, min depth/volume: symrec''s choice, not in the paper');

-- runs: one reconstruction of one instance, successful or not, with everything needed
-- to repeat it: the symmetry and every parameter value as used, the alignment found,
-- the software version, timings, and the restored mesh.
CREATE TABLE runs (
    id                INTEGER PRIMARY KEY,             -- row id
    instance_id       INTEGER NOT NULL REFERENCES instances (id) ON DELETE CASCADE,  -- the instance restored
    symmetry_kind     TEXT NOT NULL CHECK (symmetry_kind IN ('axial', 'mirror', 'glide')),  -- symmetry used
    symmetry_order    INTEGER NOT NULL DEFAULT 0       -- axial n-fold order used; 0 = continuous
                      CHECK (symmetry_order = 0 OR symmetry_order BETWEEN 2 AND 360),
    symmetry_shift_mm REAL NOT NULL DEFAULT 0 CHECK (symmetry_shift_mm >= 0),  -- glide shift used (found or given)
    params_name       TEXT NOT NULL,                   -- name of the parameter set (a copy, no foreign key)
    layers            INTEGER NOT NULL CHECK (layers BETWEEN 1 AND 100000),   -- N_layers used
    sectors           INTEGER NOT NULL CHECK (sectors BETWEEN 3 AND 100000),  -- N_sectors used
    gamma_axis        REAL NOT NULL CHECK (gamma_axis > 0 AND gamma_axis <= 1),    -- gamma_axis used
    gamma_plane       REAL NOT NULL CHECK (gamma_plane > 0 AND gamma_plane <= 1),  -- gamma_plane used
    delta_d           REAL NOT NULL CHECK (delta_d > 0 AND delta_d <= 1),          -- delta_d used
    min_depth_mm      REAL NOT NULL CHECK (min_depth_mm >= 0),                     -- min_depth_mm used
    min_volume_mm3    REAL NOT NULL CHECK (min_volume_mm3 >= 0),                   -- min_volume_mm3 used
    method            TEXT NOT NULL CHECK (length(method) >= 1),  -- which variant ran, e.g. 'paper' or 'robust'
    alignment         BLOB CHECK (alignment IS NULL OR length(alignment) = 96),  -- scan-to-aligned transform: 12 little-endian doubles, 3 by 4 row-major (mesh.h); NULL = not reached
    alignment_given   INTEGER NOT NULL DEFAULT 0 CHECK (alignment_given IN (0, 1)),  -- 1 = alignment set by the user, 0 = found by search
    fit_quality       REAL CHECK (fit_quality IS NULL OR fit_quality BETWEEN 0 AND 1),  -- fraction of layers found symmetric after alignment; NULL = not reached
    status            TEXT NOT NULL CHECK (status IN ('ok', 'failed')),  -- outcome
    error             TEXT,                            -- the error line when status = 'failed'
    software_version  TEXT NOT NULL,                   -- symrec version (SR_VERSION) that ran
    started_at        TEXT NOT NULL,                   -- start time (UTC)
    finished_at       TEXT CHECK (finished_at IS NULL OR finished_at >= started_at),  -- end time (UTC); NULL = did not finish
    restored_mesh_id  INTEGER REFERENCES meshes (id) ON DELETE SET NULL,  -- damaged scan plus patches; NULL = none
    timings_json      TEXT CHECK (timings_json IS NULL OR json_valid(timings_json)),  -- per-stage wall times, seconds, e.g. {"align":0.12}
    CHECK (status = 'ok' OR error IS NOT NULL)
) STRICT;
CREATE INDEX runs_instance ON runs (instance_id, started_at);  -- history of an instance
CREATE INDEX runs_started ON runs (started_at);                -- history by date
CREATE INDEX runs_restored_mesh ON runs (restored_mesh_id);    -- foreign key

-- run_layers: per layer of a run, the damaged outline and the restored outline (paper
-- Alg. 4/5 Polylines(0,.) and Polylines(1,.)), one point per sector in sector order at
-- height z_mm, in the aligned frame. Blob: sectors by 2 little-endian doubles (x, y);
-- a sector without a surface point is NaN, NaN.
CREATE TABLE run_layers (
    id          INTEGER PRIMARY KEY,                   -- row id
    run_id      INTEGER NOT NULL REFERENCES runs (id) ON DELETE CASCADE,  -- the run
    layer_index INTEGER NOT NULL CHECK (layer_index >= 0),  -- layer number, 0 = lowest
    z_mm        REAL NOT NULL,                         -- height of the layer in the aligned frame
    damaged     BLOB NOT NULL CHECK (length(damaged) % 16 = 0),  -- damaged outline, Polylines(0,.)
    restored    BLOB NOT NULL CHECK (length(restored) = length(damaged)),  -- restored outline, Polylines(1,.)
    UNIQUE (run_id, layer_index)
) STRICT;

-- sections: the missing sections of a run (paper Alg. 6): runs of damaged sectors
-- joined across layers, with their feature-level description and their patch mesh.
CREATE TABLE sections (
    id            INTEGER PRIMARY KEY,                 -- row id
    run_id        INTEGER NOT NULL REFERENCES runs (id) ON DELETE CASCADE,  -- the run
    section_index INTEGER NOT NULL CHECK (section_index >= 0),  -- number within the run, 0 first
    layer_first   INTEGER NOT NULL CHECK (layer_first >= 0),    -- lowest layer index covered
    layer_last    INTEGER NOT NULL CHECK (layer_last >= layer_first),  -- highest layer index covered
    z_min_mm      REAL NOT NULL,                       -- lower z in the aligned frame
    z_max_mm      REAL NOT NULL CHECK (z_max_mm >= z_min_mm),  -- upper z
    angle_from_deg REAL,                               -- axial: start of the angular range, [0, 360); NULL for planar
    angle_to_deg  REAL,                                -- axial: end of the range, counter-clockwise from angle_from_deg
    side          INTEGER CHECK (side IS NULL OR side IN (-1, 1)),  -- planar: +1 on the side the plane normal points to, -1 the other; NULL for axial
    volume_mm3    REAL NOT NULL CHECK (volume_mm3 >= 0),  -- missing volume (volume of the patch)
    area_mm2      REAL NOT NULL CHECK (area_mm2 >= 0),    -- area of the lost surface
    depth_max_mm  REAL NOT NULL CHECK (depth_max_mm >= 0),   -- largest radial/normal depth of the loss
    depth_mean_mm REAL NOT NULL CHECK (depth_mean_mm >= 0),  -- mean depth over the damaged sectors
    class         TEXT NOT NULL CHECK (length(class) >= 1),  -- damage class, e.g. 'chip', 'dent', 'broken'
    patch_mesh_id INTEGER REFERENCES meshes (id) ON DELETE SET NULL,  -- closed patch mesh; NULL = not kept
    features_json TEXT CHECK (features_json IS NULL OR json_valid(features_json)),  -- further features, e.g. {"arc_deg":12}
    CHECK ((angle_from_deg IS NULL) = (angle_to_deg IS NULL)),
    UNIQUE (run_id, section_index),
    UNIQUE (id, run_id)                                -- target of advice's (section_id, run_id) key
) STRICT;
CREATE INDEX sections_class ON sections (class);          -- history by damage class
CREATE INDEX sections_patch_mesh ON sections (patch_mesh_id);  -- foreign key

-- repair_rules: the rules advice is drawn from, editable without recompiling. A rule
-- applies to a section when every condition that is not NULL holds; among those that
-- apply the lowest priority number wins.
CREATE TABLE repair_rules (
    id                 INTEGER PRIMARY KEY,            -- row id
    name               TEXT NOT NULL UNIQUE COLLATE NOCASE  -- short unique name, e.g. 'spray-small-chip'
                       CHECK (length(name) >= 1),
    priority           INTEGER NOT NULL DEFAULT 100,   -- lower first
    symmetry_kind      TEXT CHECK (symmetry_kind IS NULL OR symmetry_kind IN ('axial', 'mirror', 'glide')),  -- condition: symmetry kind; NULL = any
    class              TEXT,                           -- condition: section class; NULL = any
    material           TEXT COLLATE NOCASE,            -- condition: material name (ignoring case); NULL = any
    min_volume_mm3     REAL CHECK (min_volume_mm3 IS NULL OR min_volume_mm3 >= 0),  -- condition: section volume >= this
    max_volume_mm3     REAL CHECK (max_volume_mm3 IS NULL OR max_volume_mm3 >= 0),  -- condition: section volume <= this
    min_depth_mm       REAL CHECK (min_depth_mm IS NULL OR min_depth_mm >= 0),      -- condition: section depth_max >= this
    max_depth_mm       REAL CHECK (max_depth_mm IS NULL OR max_depth_mm >= 0),      -- condition: section depth_max <= this
    min_lost_fraction  REAL CHECK (min_lost_fraction IS NULL OR min_lost_fraction BETWEEN 0 AND 1),  -- condition: lost volume / intact volume >= this
    max_lost_fraction  REAL CHECK (max_lost_fraction IS NULL OR max_lost_fraction BETWEEN 0 AND 1),  -- condition: lost volume / intact volume <= this
    process            TEXT NOT NULL CHECK (length(process) >= 1),  -- what to do, e.g. 'spray_forming', 'machining', 'replace'
    parameters_json    TEXT NOT NULL DEFAULT '{}' CHECK (json_valid(parameters_json)),  -- process settings, e.g. {"layer_mm":0.5}
    reason             TEXT NOT NULL,                  -- why, in one line shown with the advice
    source             TEXT NOT NULL,                  -- where the rule comes from (paper, handbook, shop practice)
    enabled            INTEGER NOT NULL DEFAULT 1 CHECK (enabled IN (0, 1)),  -- 0 = kept but not applied
    created_at         TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now')),  -- when added (UTC)
    CHECK (min_volume_mm3 IS NULL OR max_volume_mm3 IS NULL OR min_volume_mm3 <= max_volume_mm3),
    CHECK (min_depth_mm IS NULL OR max_depth_mm IS NULL OR min_depth_mm <= max_depth_mm),
    CHECK (min_lost_fraction IS NULL OR max_lost_fraction IS NULL OR min_lost_fraction <= max_lost_fraction)
) STRICT;
CREATE INDEX repair_rules_order ON repair_rules (enabled, priority);  -- rules in the order they are tried

-- advice: what the rules advised for a run, per section or for the whole part.
CREATE TABLE advice (
    id           INTEGER PRIMARY KEY,                  -- row id
    run_id       INTEGER NOT NULL REFERENCES runs (id) ON DELETE CASCADE,  -- the run
    section_id   INTEGER,                              -- the section (of the same run); NULL = whole part
    rule_id      INTEGER REFERENCES repair_rules (id) ON DELETE SET NULL,  -- the rule that gave it; NULL = rule since deleted or built in
    process      TEXT NOT NULL CHECK (length(process) >= 1),  -- process advised (copied from the rule)
    reason       TEXT NOT NULL,                        -- why (copied from the rule, with figures filled in)
    details_json TEXT NOT NULL DEFAULT '{}' CHECK (json_valid(details_json)),  -- plan: layer count and thickness, mass, allowance, ...
    created_at   TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now')),  -- when given (UTC)
    FOREIGN KEY (section_id, run_id) REFERENCES sections (id, run_id) ON DELETE CASCADE
) STRICT;
CREATE INDEX advice_run ON advice (run_id);          -- advice of a run
CREATE INDEX advice_section ON advice (section_id, run_id);  -- foreign key
CREATE INDEX advice_rule ON advice (rule_id);        -- foreign key; which rules are used

PRAGMA user_version = 1;
