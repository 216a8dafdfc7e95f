-- 014_scan_uncurled.sql: how many rim vertices of a scan were merged where a rim twisted
-- over itself in its plane (schema version 14; written and read by
-- src/catalog/catalog_scan.c, issue 16). A noisy rim of the face a part stood on can
-- fold back for an edge or two, so no fill of that face fits its rims; reconstruct
-- merges the vertices of each such twist into one at the crossing and fills the face
-- (src/mesh/scan_uncurl.c). The run keeps the count, so a restoration made over an
-- untwisted rim can be told. Runs recorded before version 14 have 0.
ALTER TABLE run_scan ADD COLUMN uncurled_vertices INTEGER NOT NULL DEFAULT 0
    CHECK (uncurled_vertices >= 0);                               -- rim vertices merged where a rim twisted in its plane

PRAGMA user_version = 14;
