-- 006_part_descriptor.sql: shape descriptors of stored meshes, the pre-filter of
-- `symrec identify` (schema version 6; src/catalog/catalog_identify.c, the figures
-- are src/align/shape_descriptor.h). Identifying a scan compares its descriptor with
-- every part's, so each part's is computed once, when the part is added with its mesh,
-- and kept here, keyed by the mesh (a part's intact mesh; the row goes with the mesh).
--
-- The backfill: SQL cannot compute a descriptor, so this migration only makes the
-- table. Parts added before it have no row; `symrec identify` (and `instance add
-- --part auto`) computes the missing ones when it runs and stores them when the
-- catalogue is writable (a read-only catalogue computes them again on every run), so
-- a migrated catalogue fills itself on its first identification.
CREATE TABLE mesh_descriptors (
    mesh_id INTEGER PRIMARY KEY REFERENCES meshes (id) ON DELETE CASCADE,  -- the mesh described
    version INTEGER NOT NULL CHECK (version >= 1),  -- SR_SHAPE_DESCRIPTOR_VERSION it was computed by; another version is recomputed
    data    BLOB NOT NULL                           -- sr_shape_descriptor_pack: version, area, 3 spreads, 144 D2 shares, 8-byte little-endian doubles
) STRICT;

PRAGMA user_version = 6;
