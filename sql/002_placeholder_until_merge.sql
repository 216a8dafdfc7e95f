-- 002_placeholder_until_merge.sql: PLACEHOLDER on branch `rules` only.
--
-- Migration 002 belongs to another branch (runs/plan); migrations must be numbered
-- without gaps, so this branch carries an empty 002 to test its 003 against. DELETE
-- THIS FILE when merging: the real 002 takes its number (two files numbered 002 make
-- the catalogue refuse to open). 003_rules.sql depends on nothing 002 adds.
PRAGMA user_version = 2;
