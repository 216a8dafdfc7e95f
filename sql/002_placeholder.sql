-- 002_placeholder.sql: stands in for migration 002 of another branch (features/rules)
-- so that this branch's 004 applies without a gap. It changes nothing but the schema
-- version. The lead replaces this file with the real 002 at merge.
PRAGMA user_version = 2;
