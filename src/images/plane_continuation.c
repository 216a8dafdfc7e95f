/*
 * plane_continuation.c: the image method's continuation across a mirror plane (see
 * plane_continuation.h): the layer method asked, in a box round the image pieces at the
 * plane, whether a loss goes on into the half no image holds.
 */
#include "images/plane_continuation.h"

#include <math.h>
#include <string.h>

#include "mesh/mesh.h"
#include "robust/region_sections.h"

#define CONTINUE_MARGIN_MM 3.0

/* Image pieces at the mirror plane, and the test a layer section must pass to take one
 * over: the layer section's box holds at least half of the piece's box, and it is not
 * a different loss (1.25 to 4 times the piece's volume). */
typedef struct plane_pieces {
    const sr_section *sec;
    size_t count;
    double reach;
} plane_pieces;

static int at_plane(const sr_section *s, double reach, double lo[3], double hi[3])
{
    sr_mesh_bbox(&s->patch, lo, hi);
    return lo[0] < reach && hi[0] > -reach;
}

static int takes_over(const double a[3], const double b[3], double volume,
                      const double lo[3], const double hi[3], double piece_volume)
{
    double common = 1, own = 1;
    for (int c = 0; c < 3; c++) {
        common *= fmax(0, fmin(b[c], hi[c]) - fmax(a[c], lo[c]));
        own *= hi[c] - lo[c];
    }
    return common >= 0.5 * own && volume >= 1.25 * piece_volume &&
           volume <= 4.0 * piece_volume;
}

/* sr_region_opts.want: only a layer section that may take over a piece gets a patch
 * (building every one took a noisy bracket's layer method 9.7 s) */
static int wanted_across(const double box[6], double volume, void *ctx)
{
    const plane_pieces *pp = ctx;
    for (size_t i = 0; i < pp->count; i++) {
        double lo[3], hi[3];
        if (at_plane(&pp->sec[i], pp->reach, lo, hi) &&
            takes_over(box, box + 3, volume, lo, hi, pp->sec[i].volume_mm3))
            return 1;
    }
    return 0;
}

sr_status sr_continue_across_plane(const sr_mesh *aligned, const sr_layer_grid *grid,
                                   const sr_continuation_opts *o, sr_section *sections,
                                   size_t count, size_t *continued, sr_err *err)
{
    (void)err;
    const sr_symmetry *sym = &o->symmetry;
    if (sym->kind != SR_SYM_MIRROR)
        return SR_OK; /* tried on glide parts too: the layer sections of noisy rails
                       * filled 80 % outside the part */
    double reach = 2.0 * o->pitch_mm;
    /* the layer method runs only in a box round the image pieces at the plane: each
     * grown by its own size (a layer section the match below takes holds at most four
     * times the piece) and CONTINUE_MARGIN_MM, symmetric about the plane; the layers
     * outside it, and the sections the box cuts, are not its answer (a noisy clamp's
     * continuation over the whole part 5.4 s, in the box 0.9 s) */
    double roi[6] = {HUGE_VAL, HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    int any = 0;
    for (size_t i = 0; i < count; i++) {
        double lo[3], hi[3];
        if (!at_plane(&sections[i], reach, lo, hi))
            continue;
        any = 1;
        for (int a = 0; a < 3; a++) {
            double grow = (hi[a] - lo[a]) + CONTINUE_MARGIN_MM;
            roi[a] = fmin(roi[a], lo[a] - grow);
            roi[3 + a] = fmax(roi[3 + a], hi[a] + grow);
        }
    }
    if (!any)
        return SR_OK;
    double half = fmax(fabs(roi[0]), fabs(roi[3]));
    roi[0] = -half;
    roi[3] = half;
    sr_region_opts ro = {.symmetry = *sym,
                         .open_mm = o->open_mm,
                         .min_depth_mm = o->min_depth_mm,
                         .min_volume_mm3 = o->min_volume_mm3,
                         .have_roi = 1,
                         .roi = {roi[0], roi[1], roi[2], roi[3], roi[4], roi[5]}};
    plane_pieces pp = {sections, count, reach};
    ro.want = wanted_across;
    ro.want_ctx = &pp;
    sr_analysis an = {0};
    sr_section *ls = NULL;
    size_t ln = 0;
    sr_err lerr = {{0}};
    if (sr_region_reconstruct(aligned, grid, &ro, &an, &ls, &ln, &lerr) != SR_OK)
        return SR_OK; /* the images' answer stands */
    sr_analysis_release(&an);
    for (size_t i = 0; i < count; i++) {
        sr_section *sec = &sections[i];
        double lo[3], hi[3];
        if (!at_plane(sec, reach, lo, hi))
            continue;
        for (size_t k = 0; k < ln; k++) {
            double a[3], b[3];
            sr_mesh_bbox(&ls[k].patch, a, b);
            if (!ls[k].patch.tri ||
                !takes_over(a, b, ls[k].volume_mm3, lo, hi, sec->volume_mm3))
                continue;
            /* a break carried across the plane goes on into the half that no image
             * holds: on the image piece's own side the layers must agree with it (add
             * at most a tenth of what they add), or it is the layer method's own
             * overfill (a generated bracket's chip beside the plane: +225 %, 760 mm3
             * added on the image's side). The lever: 257 mm3 added across, -0.6 on
             * the image's side. */
            double layer_neg, layer_pos, image_neg, image_pos;
            sr_mesh_volume_across_x(&ls[k].patch, 0.0, &layer_neg, &layer_pos);
            sr_mesh_volume_across_x(&sec->patch, 0.0, &image_neg, &image_pos);
            int image_pos_side = image_pos >= image_neg;
            double add_neg = layer_neg - image_neg, add_pos = layer_pos - image_pos;
            double add_own = image_pos_side ? add_pos : add_neg;
            double add_across = image_pos_side ? add_neg : add_pos;
            if (!(add_across > 0) || add_own > 0.1 * add_across)
                continue;
            /* the layer patch alone (it is grown into the scan, so it covers what the
             * image did): a union with the image piece would leave slivers where the
             * two run together */
            sr_mesh_release(&sec->patch);
            sec->patch = ls[k].patch;
            memset(&ls[k].patch, 0, sizeof ls[k].patch);
            sec->volume_mm3 = sr_mesh_volume(&sec->patch);
            (*continued)++;
            break;
        }
    }
    sr_sections_release(ls, ln);
    return SR_OK;
}
