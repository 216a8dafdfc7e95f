-- 006_part_descriptor.sql: PLACEHOLDER so that this branch migrates (replaced on merge).
PRAGMA user_version = 6;
