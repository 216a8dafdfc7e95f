-- PLACEHOLDER for 005_mesh_units.sql (another branch); replaced on merge.
PRAGMA user_version = 5;
