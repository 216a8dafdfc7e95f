-- 003_placeholder.sql: stands in for migration 003 of another branch (build plan) so
-- that this branch's 004 applies without a gap. It changes nothing but the schema
-- version. The lead replaces this file with the real 003 at merge.
PRAGMA user_version = 3;
