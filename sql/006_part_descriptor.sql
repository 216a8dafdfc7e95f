-- PLACEHOLDER for 006_part_descriptor.sql (another branch); replaced on merge.
PRAGMA user_version = 6;
