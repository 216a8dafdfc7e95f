/*
 * rules.h: the repair-rule engine. It turns the feature-level description of a run's
 * missing sections (section_features.h) into advice (the paper's expert advice for repair by
 * spray forming, section 7 / Figure 8), drawing on rules and a material given as plain
 * rows (rule.h). Pure C, no SQLite: the catalogue keeps the rows the shop edits and
 * hands them in (catalog_record.h), so the shop changes the advice by editing rows.
 *
 * How rules are applied:
 *   * the enabled rules are tried in order of priority (lower first), then id;
 *   * a rule's conditions are its non-NULL condition columns; the rule holds when all
 *     hold. A condition that cannot be evaluated (the part has no material, or its
 *     material no family; a feature the section does not have; the part volume is
 *     unknown for a fraction) is "unknown": with three-valued logic a rule with an
 *     unknown condition is false if another of its conditions is false, else unknown.
 *     Unknown rules are reported in the advice ("rules_unevaluated", each with why and
 *     whether it outranks the rule applied), never skipped silently;
 *   * scope 'part' rules are tried once on the whole part (lost fraction = sum of the
 *     sections' volumes / part volume; class/location hold if any section has them;
 *     volume is the total; depth, depth fraction and section fraction the largest);
 *     the first that holds gives the whole-part advice (section_index -1), e.g.
 *     "replace: beyond repair" above the paper's 25 % of lost volume;
 *   * scope 'section' rules are tried on each section; the first that holds and whose
 *     process the material allows gives that section's advice. A rule that holds but
 *     whose process the material's row in material_process_limits marks unsuitable, or
 *     whose section is deeper than that row's max_depth_mm, is passed over and reported
 *     ("rules_blocked");
 *   * every advice names the rules that held ("rules_fired", in the order tried; the
 *     first not blocked is "applied"). When none holds (no catch-all rule) the advice is
 *     process "manual_review" with rule_id 0 and reason "no enabled rule applies".
 * details_json of an advice:
 *   {"applied": name|null, "rules_fired": [names], "rules_blocked": [{"rule","why"}],
 *    "rules_unevaluated": [{"rule","scope","why","outranks_applied"}],
 *    "parameters": {the rule's parameters_json}, "class", "location",
 *    "material": name|null, "density_g_cm3", "missing_mass_g", "lost_fraction",
 *    "part_advice": name (sections only, when a whole-part advice exists),
 *    "preheat_c" (when the material's limit row gives one)}
 * The reason is the rule's reason with {figure} filled in from the section's figures
 * (section_features.h names) and {class}, {location}, {material}, {lost_fraction_pct},
 * {part_fraction_pct}; an unknown name is left as written.
 */
#ifndef SR_RULES_H
#define SR_RULES_H

#include <stddef.h>

#include "advice/rule.h"
#include "advice/section_features.h"
#include "run/run.h"
#include "base/status.h"

/* What the engine knows of the part besides its sections. */
typedef struct sr_rule_part {
    const char *material;           /* name; NULL or "" = none given */
    const sr_material *info;        /* the material's row and limits; NULL = not in the
                                     * catalogue (then family/limits are unknown) */
    sr_sym_kind symmetry;           /* SR_SYM_NONE = unknown */
    double volume_mm3;              /* intact (or restored) part volume; <= 0 = unknown */
    double lost_fraction;           /* sum of the sections' volumes / volume_mm3; NaN =
                                     * unknown. sr_rules_advise computes it itself. */
} sr_rule_part;

typedef enum sr_rule_verdict {
    SR_RULE_NO = 0,
    SR_RULE_YES = 1,
    SR_RULE_UNKNOWN = 2,
} sr_rule_verdict;

/* Evaluates the conditions of one section-scope rule on one section (f), or of a
 * part-scope rule on the whole part (f = the run's sections, count f_count). On
 * SR_RULE_UNKNOWN, why (size bytes) says which condition could not be evaluated. */
sr_rule_verdict sr_rule_evaluate(const sr_rule *rule, const sr_rule_part *part,
                                 const sr_features *f, size_t f_count, char *why, size_t size);

/* Advice for a run from `rules` (in the order to try them; disabled ones are skipped)
 * and the sections' descriptions fs (one per run->sections[i]): the whole-part advice
 * first if a part rule holds, then one per section. *out (heap array of *count,
 * each details_json heap; free with free()) only on success. */
sr_status sr_rules_advise(const sr_rule *rules, size_t rule_count, const sr_rule_part *part,
                          const sr_run *run, const sr_features *fs, sr_run_advice **out,
                          size_t *count, sr_err *err);

/* Describes every section (sr_features_compute: damage_class, features_json) and
 * replaces run->advice (freeing what was there) with sr_rules_advise's from `rules`
 * (rule_count, in the order to try them; disabled ones are skipped). `material` is the
 * part's material name (NULL or "" = none) and `info` its row with limits (NULL = not
 * known: a name without a row keeps its name, with family and limits unknown).
 * part_volume_mm3 <= 0 = unknown. All or nothing: on failure the run is as it was.
 * The catalogue's version, with its rules and material rows, is catalog_record.h's
 * sr_catalog_advise_run. */
sr_status sr_advise_run(const sr_rule *rules, size_t rule_count, const char *material,
                        const sr_material *info, double part_volume_mm3, sr_run *run,
                        sr_err *err);

#endif
