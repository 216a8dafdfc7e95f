-- 005_placeholder.sql: PLACEHOLDER for migration 005 of another branch (drop on merge).
PRAGMA user_version = 5;
