-- 005_mesh_units.sql: the unit each stored mesh was drawn in (schema version 5; read and
-- written by src/catalog/catalog_mesh.c). symrec stores every mesh in millimetres: a file
-- drawn in another unit is scaled to mm as it is read (`--units`, default the format's
-- own: mm for STL/OBJ/PLY/OFF, metres for glTF/GLB). The unit it was read in is kept
-- with the mesh, so `part show` and `instance show` can say how the scan came in, and a
-- mesh stored from a file read in the wrong unit can be found.
--
-- Meshes stored before this migration were all read as millimetres (symrec asked no
-- unit), so they take 'mm'; so do meshes symrec builds itself (restored parts, patches).

ALTER TABLE meshes ADD COLUMN
    source_unit TEXT NOT NULL DEFAULT 'mm'
    CHECK (source_unit IN ('mm', 'cm', 'm', 'in'));  -- unit the source file was drawn in; the stored coordinates are mm whatever it was

PRAGMA user_version = 5;
