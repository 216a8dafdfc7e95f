-- PLACEHOLDER for 007_symmetry_proposal.sql (another branch); replaced on merge.
PRAGMA user_version = 7;
