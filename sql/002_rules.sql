-- 002_rules.sql: what the repair-rule engine (src/rules.c) needs (schema version 2):
-- more conditions on repair_rules, a family per material, per-material process limits
-- (material_process_limits), the common shop materials with their densities, and the
-- seed rules, each with the source of its thresholds.
--
-- How a rule is read (src/rules.h has the full statement):
--   * a rule of scope 'section' is tried on every missing section of a run, a rule of
--     scope 'part' once on the whole part; its conditions are the non-NULL condition
--     columns, all of which must hold;
--   * enabled rules are tried in order of priority (lower first, then id); the first
--     whose conditions hold and whose process the part's material allows (table
--     material_process_limits) gives the advice; every rule whose conditions held is
--     named in the advice (details_json.rules_fired);
--   * a condition that cannot be evaluated (no material given, a feature the section
--     does not have, part volume unknown) makes the rule 'unevaluated' unless another
--     of its conditions is false anyway; such rules are listed in the advice
--     (details_json.rules_unevaluated), never skipped silently.
-- Editing a row (with `symrec rules set` or plain SQL) changes the next advice: nothing
-- is compiled in. parameters_json keys used by the build plan: layer_mm (deposited
-- layer height), step_over_mm (path spacing), allowance_mm (machining stock added on
-- every surface), deposition_rate_g_min (deposit per minute), efficiency (fraction of
-- fed material that stays on the part).

-- ---- repair_rules: further conditions (NULL = any, as for the columns of 001) ----
ALTER TABLE repair_rules ADD COLUMN scope TEXT NOT NULL DEFAULT 'section'
    CHECK (scope IN ('section', 'part'));  -- 'section': tried on each missing section; 'part': once on the whole part (its advice has section_index -1)
ALTER TABLE repair_rules ADD COLUMN material_family TEXT
    CHECK (material_family IS NULL OR material_family IN
           ('steel', 'stainless_steel', 'cast_iron', 'aluminium', 'copper', 'titanium', 'nickel'));  -- condition: family of the part's material (materials.family); NULL = any
ALTER TABLE repair_rules ADD COLUMN location TEXT
    CHECK (location IS NULL OR location IN ('shoulder', 'end_face', 'body', 'ear', 'arm', 'edge'));  -- condition: the section lies at this feature of the part (features_json.locations, src/features.h); NULL = any
ALTER TABLE repair_rules ADD COLUMN min_depth_fraction REAL
    CHECK (min_depth_fraction IS NULL OR min_depth_fraction BETWEEN 0 AND 1);  -- condition: depth_max / local restored radius >= this
ALTER TABLE repair_rules ADD COLUMN max_depth_fraction REAL
    CHECK (max_depth_fraction IS NULL OR (max_depth_fraction BETWEEN 0 AND 1
           AND (min_depth_fraction IS NULL OR min_depth_fraction <= max_depth_fraction)));  -- condition: depth_max / local restored radius <= this
ALTER TABLE repair_rules ADD COLUMN min_section_fraction REAL
    CHECK (min_section_fraction IS NULL OR min_section_fraction BETWEEN 0 AND 1);  -- condition: section volume / part volume >= this (part scope: the largest section)
ALTER TABLE repair_rules ADD COLUMN max_section_fraction REAL
    CHECK (max_section_fraction IS NULL OR (max_section_fraction BETWEEN 0 AND 1
           AND (min_section_fraction IS NULL OR min_section_fraction <= max_section_fraction)));  -- condition: section volume / part volume <= this
ALTER TABLE repair_rules ADD COLUMN feature TEXT
    CHECK (feature IS NULL OR length(CAST(feature AS BLOB)) BETWEEN 1 AND 63);  -- condition on any numeric feature of the section by its key in features_json (e.g. 'arc_deg', 'aspect'); alone = the section has it
ALTER TABLE repair_rules ADD COLUMN feature_min REAL
    CHECK (feature_min IS NULL OR feature IS NOT NULL);  -- condition: that feature >= this
ALTER TABLE repair_rules ADD COLUMN feature_max REAL
    CHECK (feature_max IS NULL OR (feature IS NOT NULL
           AND (feature_min IS NULL OR feature_min <= feature_max)));  -- condition: that feature <= this
ALTER TABLE repair_rules ADD COLUMN updated_at TEXT;  -- when the row was last changed (UTC), by the API or by plain SQL (trigger below); NULL = never since added

-- Any UPDATE that does not set updated_at itself stamps it, so edits made with plain
-- SQL are visible in `symrec rules show` too.
CREATE TRIGGER repair_rules_touch AFTER UPDATE ON repair_rules
    WHEN NEW.updated_at IS OLD.updated_at
BEGIN
    UPDATE repair_rules SET updated_at = strftime('%Y-%m-%dT%H:%M:%SZ', 'now') WHERE id = NEW.id;
END;

-- ---- materials: a family, so rules and limits can speak of 'cast_iron' at once ----
ALTER TABLE materials ADD COLUMN family TEXT
    CHECK (family IS NULL OR family IN
           ('steel', 'stainless_steel', 'cast_iron', 'aluminium', 'copper', 'titanium', 'nickel'));  -- material family; NULL = not known

-- material_process_limits: whether a repair process suits a material, and within what
-- limits. A rule whose process a material's row marks unsuitable, or whose section is
-- deeper than max_depth_mm, is passed over for that material (reported in the advice
-- as details_json.rules_blocked). No row = no known limit.
CREATE TABLE material_process_limits (
    id           INTEGER PRIMARY KEY,                  -- row id
    material_id  INTEGER NOT NULL REFERENCES materials (id) ON DELETE CASCADE,  -- the material
    process      TEXT NOT NULL                         -- the process, as in repair_rules.process
                 CHECK (length(CAST(process AS BLOB)) BETWEEN 1 AND 63),
    suitable     INTEGER NOT NULL CHECK (suitable IN (0, 1)),  -- 1 = usable on this material, 0 = do not use
    max_depth_mm REAL CHECK (max_depth_mm IS NULL OR max_depth_mm > 0),  -- deepest section this process may rebuild on this material; NULL = no limit known
    preheat_c    REAL CHECK (preheat_c IS NULL OR preheat_c >= 0),  -- preheat temperature to plan for, deg C; NULL = none/not known
    notes        TEXT NOT NULL DEFAULT '',             -- why, in one line shown with the advice
    source       TEXT NOT NULL,                        -- where the limit comes from
    UNIQUE (material_id, process)                      -- one row per pair; also the index of the foreign key
) STRICT;

-- ---- common shop materials (densities at room temperature, g/cm^3) ----
-- A material already named by a part keeps its row; a missing density or family is
-- filled in, a density the shop has set is kept.
INSERT INTO materials (name, density_g_cm3, family, notes) VALUES
    ('42CrMo4', 7.85, 'steel', 'EN 10083-3 quenched and tempered Cr-Mo steel (AISI 4140); density typical of low-alloy steel'),
    ('C45', 7.85, 'steel', 'EN 10083-2 unalloyed medium-carbon steel (AISI 1045)'),
    ('X5CrNi18-10', 7.90, 'stainless_steel', 'EN 10088 1.4301 austenitic stainless steel (AISI 304)'),
    ('EN-GJL-250', 7.20, 'cast_iron', 'EN 1561 grey cast iron with flake graphite'),
    ('EN-GJS-400-15', 7.10, 'cast_iron', 'EN 1563 ductile (spheroidal graphite) cast iron'),
    ('EN AW-6082', 2.70, 'aluminium', 'EN 573 AlSi1MgMn wrought aluminium alloy, usually T6'),
    ('EN AW-7075', 2.81, 'aluminium', 'EN 573 AlZn5.5MgCu high-strength wrought aluminium alloy'),
    ('CuSn12', 8.70, 'copper', 'EN 1982 cast tin bronze (bearing and gear bronze)'),
    ('Ti-6Al-4V', 4.43, 'titanium', 'ASTM B348 grade 5 titanium alloy')
ON CONFLICT (name) DO UPDATE SET
    density_g_cm3 = COALESCE(materials.density_g_cm3, excluded.density_g_cm3),
    family = COALESCE(materials.family, excluded.family);

-- ---- process limits of those materials ----
-- The processes: spray_forming (the paper's: sprayed metal built up layer by layer,
-- its Figure 8; in a shop today thermal or cold spray), ded (directed energy
-- deposition / laser cladding: a fused, metallurgically bonded deposit), weld_buildup
-- (arc-welded build-up, then machining). These are general weldability facts stated
-- conservatively, not a qualified welding procedure: a shop sets its own.
WITH v (name, process, suitable, max_depth_mm, preheat_c, notes, source) AS (VALUES
    ('42CrMo4', 'weld_buildup', 1, NULL, 300, 'hardenable (carbon equivalent about 0.9): preheat and temper after welding',
     'general weldability guidance for Cr-Mo steels (carbon equivalent method); preheat value shop practice, conservative'),
    ('42CrMo4', 'ded', 1, NULL, 250, 'small heat input, still preheat to avoid martensite cracking',
     'shop practice, conservative'),
    ('42CrMo4', 'spray_forming', 1, NULL, NULL, 'no fusion of the base metal', 'shop practice'),
    ('C45', 'weld_buildup', 1, NULL, 200, 'medium carbon: preheat', 'general weldability guidance (carbon equivalent about 0.55); shop practice'),
    ('C45', 'ded', 1, NULL, 150, '', 'shop practice, conservative'),
    ('C45', 'spray_forming', 1, NULL, NULL, '', 'shop practice'),
    ('X5CrNi18-10', 'weld_buildup', 1, NULL, NULL, 'austenitic: no preheat', 'general weldability guidance for austenitic stainless steel'),
    ('X5CrNi18-10', 'ded', 1, NULL, NULL, '', 'shop practice'),
    ('X5CrNi18-10', 'spray_forming', 1, NULL, NULL, '', 'shop practice'),
    ('EN-GJL-250', 'weld_buildup', 0, NULL, NULL, 'grey iron cracks when fusion welded (graphite flakes, hard heat-affected zone)',
     'general weldability guidance for grey cast iron; hot welding with nickel filler exists but is left to a specialist (conservative)'),
    ('EN-GJL-250', 'ded', 1, 3.0, 300, 'nickel-based powder, shallow builds only', 'shop practice, conservative'),
    ('EN-GJL-250', 'spray_forming', 1, NULL, NULL, 'spraying does not melt the base: the usual cast-iron repair', 'shop practice'),
    ('EN-GJS-400-15', 'weld_buildup', 0, NULL, NULL, 'ductile iron: fusion welding only by a qualified procedure', 'shop practice, conservative'),
    ('EN-GJS-400-15', 'ded', 1, 5.0, 250, 'nickel-based powder', 'shop practice, conservative'),
    ('EN-GJS-400-15', 'spray_forming', 1, NULL, NULL, '', 'shop practice'),
    ('EN AW-6082', 'weld_buildup', 1, NULL, NULL, 'TIG/MIG with 4043/5356 filler; the heat-affected zone loses its T6 strength',
     'general weldability guidance for 6xxx aluminium alloys'),
    ('EN AW-6082', 'ded', 1, NULL, NULL, 'porosity risk: dry powder, inert gas', 'shop practice'),
    ('EN AW-6082', 'spray_forming', 1, NULL, NULL, 'cold spray is the usual aluminium repair', 'shop practice'),
    ('EN AW-7075', 'weld_buildup', 0, NULL, NULL, 'hot cracking: 7075 is not fusion weldable', 'general weldability guidance for 7xxx Al-Zn-Mg-Cu alloys'),
    ('EN AW-7075', 'ded', 0, NULL, NULL, 'fusion deposit cracks like a weld', 'general weldability guidance for 7xxx alloys; conservative'),
    ('EN AW-7075', 'spray_forming', 1, NULL, NULL, 'cold spray (no melting) is the repair used for 7075', 'shop practice'),
    ('CuSn12', 'weld_buildup', 1, NULL, 200, 'TIG with bronze filler', 'shop practice'),
    ('CuSn12', 'ded', 1, NULL, NULL, '', 'shop practice'),
    ('CuSn12', 'spray_forming', 1, NULL, NULL, '', 'shop practice'),
    ('Ti-6Al-4V', 'weld_buildup', 1, NULL, NULL, 'only under full inert-gas shielding (trailing shield or chamber)', 'general weldability guidance for titanium'),
    ('Ti-6Al-4V', 'ded', 1, NULL, NULL, 'in an argon chamber; oxygen pick-up embrittles', 'shop practice'),
    ('Ti-6Al-4V', 'spray_forming', 1, NULL, NULL, 'cold spray only: combustion or plasma spray in air oxidises titanium', 'shop practice, conservative')
)
INSERT INTO material_process_limits (material_id, process, suitable, max_depth_mm, preheat_c, notes, source)
SELECT m.id, v.process, v.suitable, v.max_depth_mm, v.preheat_c, v.notes, v.source
FROM v JOIN materials m ON m.name = v.name
WHERE NOT EXISTS (SELECT 1 FROM material_process_limits l
                  WHERE l.material_id = m.id AND l.process = v.process);

-- ---- seed rules ----
-- reason texts may name figures in braces ({depth_max_mm}, {lost_fraction_pct}, any
-- feature key): the advice carries them filled in.
INSERT INTO repair_rules (name, priority, scope, class, location, min_depth_mm, max_depth_mm,
                          min_lost_fraction, min_depth_fraction, max_section_fraction,
                          process, parameters_json, reason, source) VALUES
    ('replace-beyond-25pct', 10, 'part', NULL, NULL, NULL, NULL, 0.25, NULL, NULL,
     'replace', '{}',
     'replace: beyond repair: {lost_fraction_pct} % of the part''s volume is missing',
     'paper, section 1: the reconstruction (and the spray-forming repair it feeds) assumes up to about 25 % loss of the original volume'),
    ('crack-grind-and-inspect', 20, 'section', 'crack', NULL, NULL, NULL, NULL, NULL, NULL,
     'inspect', '{"allowance_mm":0.5}',
     'crack-like narrow loss {depth_max_mm} mm deep: grind out to sound metal and check by dye-penetrant or magnetic-particle testing before any build-up',
     'shop practice, conservative: weld-repair procedures require a crack to be removed and the groove checked by NDT before depositing; a deposit over a live crack hides it'),
    ('broken-feature-ded', 30, 'section', 'broken_feature', NULL, NULL, NULL, NULL, NULL, NULL,
     'ded', '{"layer_mm":1.0,"step_over_mm":1.5,"allowance_mm":1.0,"deposition_rate_g_min":15,"efficiency":0.8}',
     'broken-off feature ({depth_fraction} of the local radius deep): rebuild near net shape by directed energy deposition, then machine',
     'shop practice: DED/laser metal deposition rebuilds missing features (blade tips, teeth, lugs) with a fused deposit; parameters typical of powder DED, conservative'),
    ('shoulder-ded', 40, 'section', NULL, 'shoulder', NULL, NULL, NULL, 0.1, NULL,
     'ded', '{"layer_mm":0.8,"step_over_mm":1.2,"allowance_mm":0.8,"deposition_rate_g_min":10,"efficiency":0.8}',
     'loss at a shoulder (stress raiser), {depth_max_mm} mm deep: fused deposit by laser cladding rather than spray',
     'shop practice, conservative: a sprayed deposit is held mainly mechanically; at a shoulder or fillet, where stress concentrates, a metallurgically bonded deposit is preferred'),
    ('wear-band-spray', 50, 'section', 'wear_band', NULL, NULL, 1.5, NULL, NULL, NULL,
     'spray_forming', '{"layer_mm":0.1,"step_over_mm":3.0,"allowance_mm":0.3,"deposition_rate_g_min":50,"efficiency":0.6}',
     'shallow wear band ({depth_max_mm} mm): spray all round, then grind to size',
     'shop practice: thermal spraying ("metallizing") of worn journals is the standard repair for shallow wear; 1.5 mm is a conservative limit of a sprayed build-up'),
    ('spray-small-loss', 60, 'section', NULL, NULL, NULL, 3.0, NULL, NULL, 0.05,
     'spray_forming', '{"layer_mm":0.25,"step_over_mm":2.0,"allowance_mm":0.5,"deposition_rate_g_min":30,"efficiency":0.6}',
     'small local loss ({depth_max_mm} mm deep, {volume_mm3} mm3): spray-form it layer by layer, then machine',
     'paper, section 7 and Figure 8 (spray forming layer by layer along a tool path); depth limit 3 mm and 5 % of the part: shop practice, conservative (thick sprayed deposits build residual stress and may debond)'),
    ('ded-medium-depth', 70, 'section', NULL, NULL, NULL, 10.0, NULL, NULL, NULL,
     'ded', '{"layer_mm":0.8,"step_over_mm":1.2,"allowance_mm":0.8,"deposition_rate_g_min":10,"efficiency":0.8}',
     'loss {depth_max_mm} mm deep: laser cladding / directed energy deposition in layers, then machine',
     'shop practice: laser-clad beads are about 0.5 to 1.5 mm high, so builds up to about 10 mm are a few layers; deeper builds go faster by arc welding'),
    ('weld-buildup-deep', 80, 'section', NULL, NULL, 10.0, NULL, NULL, NULL, NULL,
     'weld_buildup', '{"layer_mm":2.5,"step_over_mm":4.0,"allowance_mm":2.0,"deposition_rate_g_min":60,"efficiency":0.9}',
     'deep loss ({depth_max_mm} mm): arc-welded build-up, then machining',
     'shop practice: arc welding deposits several kg/h, the economical choice for builds deeper than about 10 mm'),
    ('catch-all-review', 1000, 'section', NULL, NULL, NULL, NULL, NULL, NULL, NULL,
     'manual_review', '{}',
     'no specific rule matched this {class}: refer it to the repair engineer',
     'symrec: catch-all so that every section gets an advice');

PRAGMA user_version = 2;
