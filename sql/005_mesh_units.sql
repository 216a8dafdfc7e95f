-- 005_mesh_units.sql: PLACEHOLDER so that this branch migrates (replaced on merge).
PRAGMA user_version = 5;
