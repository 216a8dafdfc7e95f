-- 012_scan_sealed.sql: how much of a scan was cut out and closed again round the
-- defects its closing left (schema version 12; written and read by
-- src/catalog/catalog_scan.c, issue 16). Closing a scan's openings can leave a few
-- edges used other than once each way where rims that could not be filled cleanly
-- met; reconstruct then takes out the triangles round them and closes the opening so
-- left (src/mesh/scan_seal.c). The run keeps how many triangles that took, so a
-- restoration made over a sealed spot can be told. Runs recorded before version 12
-- have 0.
ALTER TABLE run_scan ADD COLUMN sealed_triangles INTEGER NOT NULL DEFAULT 0
    CHECK (sealed_triangles >= 0);                                -- triangles cut out round the closing's defects and closed again

PRAGMA user_version = 12;
