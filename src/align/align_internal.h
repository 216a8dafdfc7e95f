/*
 * align_internal.h: the private interface between the files that implement align.h.
 * Not installed, not used outside src/align*.c.
 *
 *   align_math.c     small dense linear algebra (symmetric eigen, SPD solve), frames
 *   align_surface.c  the scan as a surface: per-triangle normals/areas, area moments,
 *                    area-uniform sample points, and a uniform grid answering
 *                    "closest point of the surface to p" (no library)
 *   align_icp.c      the symmetry models (rotation about an axis, reflection in a
 *                    plane, glide reflection) and one robust ICP engine that fits any
 *                    of them: the model maps the surface to itself, so each sample's
 *                    image must lie on the surface
 *   align_egi.c      candidate plane normals from the normals alone (reflection
 *                    symmetry of the extended Gaussian image)
 *   align_axial.c    axial: normal-line (Pottmann-Randrup) estimate + candidates + ICP
 *   align_planar.c   mirror and glide: plane candidates, shift search, ICP
 *   align_paper.c    the paper's Algorithm 1 (fast layer) and Algorithm 3 (heuristic
 *                    alignment by counting symmetric layers over a grid of rotations)
 *   align.c          the public entry points: validation, canonical frame, override
 *   surface_query.c  align_surface.c's closest points and samples for other modules
 *                    (surface_query.h)
 */
#ifndef SR_ALIGN_INTERNAL_H
#define SR_ALIGN_INTERNAL_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "align/align.h"
#include "mesh/mesh.h"
#include "base/status.h"
#include "base/symmetry.h"

/* ---- 3-vectors ---- */

static inline double v3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void v3_cross(const double a[3], const double b[3], double out[3])
{
    double r[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                   a[0] * b[1] - a[1] * b[0]};
    out[0] = r[0];
    out[1] = r[1];
    out[2] = r[2];
}

static inline double v3_norm(const double a[3])
{
    return sqrt(v3_dot(a, a));
}

/* Normalises a in place; returns its former length (a unchanged when 0). */
static inline double v3_normalize(double a[3])
{
    double n = v3_norm(a);
    if (n > 0) {
        a[0] /= n;
        a[1] /= n;
        a[2] /= n;
    }
    return n;
}

/* ---- align_math.c ---- */

/* Eigen-decomposition of a symmetric n x n matrix (n <= 8, row-major a) by cyclic
 * Jacobi. w gets the n eigenvalues in ascending order; column k of v (v[i*n + k]) is
 * the unit eigenvector of w[k]. */
void al_eig_sym(int n, const double *a, double *w, double *v);

/* Solves a x = b for a symmetric positive (semi-)definite n x n matrix (n <= 8) by
 * Cholesky. Returns false when a pivot is not positive (x untouched). */
bool al_solve_spd(int n, const double *a, const double *b, double *x);

/* Two unit vectors u, v with (u, v, d) a right-handed orthonormal frame; d must be a
 * unit vector. */
void al_perp_frame(const double d[3], double u[3], double v[3]);

/* Rotation matrix (3x3 row-major) by angle `ang` (radians) about unit axis `k`. */
void al_rot_axis(const double k[3], double ang, double r[9]);

/* ---- align_surface.c ---- */

#define AL_THREADS_MAX 8 /* query threads a surface serves at once */
#define AL_PARALLEL_MIN 256 /* a loop of fewer queries than this runs on one thread */

typedef struct al_surface {
    const sr_mesh *mesh;
    size_t count;          /* triangles with non-zero area */
    uint32_t *tri;         /* count indices into mesh->tri; NULL when every triangle has
                            * an area (the identity: use al_tri_of) */
    float *nrm;            /* count by 3 unit outward normals, rounded to float: only to
                            * skip far triangles (with a margin); the exact normal is
                            * recomputed where it is used (al_surface_normal) */
    double total_area;
    double centroid[3];    /* area centroid of the surface */
    double cov[9];         /* area-weighted covariance of the surface about centroid */
    double bmin[3], bmax[3];
    double diag;           /* bounding-box diagonal, mm */
    /* uniform grid of triangles (indices into tri) for closest-point queries, stored by
     * bricks of 4 x 4 x 4 cells: only bricks the surface passes through hold cells */
    double origin[3];
    double cell;
    int dim[3];            /* cells */
    int bdim[3];           /* bricks */
    uint32_t *brick_slot;  /* per brick: its slot, or UINT32_MAX (no triangle) */
    uint32_t *cell_start;  /* slots * 64 + 1 offsets into cell_items */
    uint32_t *cell_items;
    uint8_t *brick_rings;  /* per brick: Chebyshev distance (in bricks, <= 255) to the
                            * nearest brick holding a triangle */
    /* per query thread: the last query that tested each of the count triangles */
    uint32_t *stamp[AL_THREADS_MAX];
    uint32_t stamp_id[AL_THREADS_MAX];
    int threads; /* threads a loop of queries may use (al_surface_threads) */
} al_surface;

/* The mesh triangle of surface triangle i. */
static inline size_t al_tri_of(const al_surface *s, size_t i)
{
    return s->tri ? (size_t)s->tri[i] : i;
}

/* Unit normal (exactly as the surface was built) and area of surface triangle i. */
void al_surface_normal(const al_surface *s, size_t i, double n[3], double *area);

/* Builds the surface data and grid of a validated mesh. SR_E_INVALID when no triangle
 * has an area, SR_E_NOMEM. On failure *s is released. */
sr_status al_surface_build(al_surface *s, const sr_mesh *mesh, sr_err *err);
void al_surface_release(al_surface *s);

/* Lets `threads` threads query s at once (0: as many as OpenMP gives, at most
 * AL_THREADS_MAX): each gets its own stamps, 4 bytes a triangle. A built surface serves
 * one. A loop of queries spread over OpenMP threads passes num_threads(s->threads);
 * every query's answer is the same from any thread. SR_E_NOMEM. */
sr_status al_surface_threads(al_surface *s, int threads);

/* Closest point of the surface to p among points within max_dist. Returns false when
 * there is none. q: the closest point, n: its triangle's unit normal, *dist: |p - q|. */
bool al_surface_closest(al_surface *s, const double p[3], double max_dist, double q[3],
                        double n[3], double *dist);

/* Area-uniform points on the surface (stratified, deterministic for a given seed). */
typedef struct al_samples {
    size_t count;
    double *p;             /* count by 3 */
    double *n;             /* count by 3: unit normal of the triangle sampled */
} al_samples;

sr_status al_samples_make(const al_surface *s, size_t count, uint64_t seed,
                          al_samples *out);
void al_samples_release(al_samples *smp);

/* ---- register.c ---- */

/* How hard al_register_fit works: the start turns about each principal axis (12 =
 * 30 degree steps), the first Tukey cut-off of the coarse ICP (share of the fixed
 * surface's diagonal: the farther, the costlier each closest-point query), ICP steps
 * for every start on the coarse samples, how many of the best go on to the medium
 * ones, steps there and on the fine ones; give_up > 0: when fewer than this share of
 * the coarse samples lie within 4 tol at the best coarse pose, that pose is the result
 * (no medium or fine stage: the surfaces do not match). */
typedef struct al_register_effort {
    int turns;
    double coarse_cutoff;
    int coarse_iters;
    size_t keep;
    int medium_iters, fine_iters;
    double give_up;
    size_t coarse_keep; /* > 0: after one coarse step, only this many starts go on */
} al_register_effort;

/* The registration of register.h on prepared surfaces and samples of the moving one
 * (coarse: a few hundred, medium: about a thousand, fine: the final fit): mat (3 x 4
 * row-major) takes the moving surface onto the fixed one. scratch holds as many
 * doubles as the largest sample set. Writes fix's query stamps, so one thread per
 * fixed surface. */
void al_register_fit(al_surface *fix, const al_surface *mov, const al_samples *coarse,
                     const al_samples *medium, const al_samples *fine, double tol,
                     const al_register_effort *effort, double mat[12], double *scratch);

/* ---- shape_descriptor.c ---- */

/* sr_shape_descriptor_compute on a built surface (for a caller that has one).
 * SR_E_NOMEM; *out only on SR_OK. */
struct sr_shape_descriptor;
sr_status al_shape_describe(const al_surface *s, struct sr_shape_descriptor *out);

/* ---- align_icp.c ---- */

enum { AL_AXIAL = 1, AL_MIRROR, AL_GLIDE };

#define AL_MAX_VARIANTS 360
#define AL_MAX_PARAMS 5

/* A symmetry transform family. The state is the symmetry element; `variant` picks
 * one of several transforms of the same element (rotation angles of an axial model;
 * +shift / -shift of a glide). Every variant maps the intact surface onto itself. */
typedef struct al_model {
    int kind;
    double a[3];           /* axial: axis direction; planar: plane normal (unit) */
    double c[3];           /* a point on the axis / in the plane */
    double t[3];           /* glide: unit shift direction in the plane */
    double shift;          /* glide: shift along t, mm */
    int fix_shift;         /* glide: the shift is given, not fitted */
    double scale;          /* length scale of position parameters, mm (part size) */
    int variant_count;
    double angle[AL_MAX_VARIANTS]; /* axial: rotation angle of each variant, radians */
} al_model;

/* Number of free parameters of the model (axial 4, mirror 3, glide 4 or 5). */
int al_model_nparam(const al_model *m);

/* The 3x4 affine matrix of variant `variant` of the model moved by the local
 * parameter step `delta` (al_model_nparam entries; NULL = no step). */
void al_model_matrix(const al_model *m, const double *delta, int variant, double mat[12]);

/* Moves the model by a local parameter step (re-orthonormalising its frame). */
void al_model_step(al_model *m, const double *delta);

/* How well a model maps the surface onto itself. */
typedef struct al_fit {
    double inlier_rms;     /* RMS closest-point distance over the inliers, mm */
    double score;          /* share of samples whose image is within tol of the surface */
    double median;         /* median closest-point distance (unmatched count as far) */
    double tol;            /* the inlier tolerance used, mm */
    int iterations;        /* ICP iterations run */
} al_fit;

/* Robust ICP starting at *m (see align_icp.c): point-to-plane residuals, Tukey weights
 * with a cut-off annealed from tau0 (mm, the first match radius) towards the robust
 * scale, Gauss-Newton steps limited so no sample moves by more than half the cut-off.
 * At most max_iter iterations. Leaves the refined model in *m and its evaluation
 * against tol in *fit (a failed allocation leaves *m as it was). */
void al_icp(al_surface *s, const al_samples *smp, al_model *m, int max_iter, double tau0,
            double tol, al_fit *fit);

/* Evaluation only: share of samples within tol, inlier RMS, median (distances beyond
 * tol are not searched: they count as infinite). */
void al_evaluate(al_surface *s, const al_samples *smp, const al_model *m, double tol,
                 al_fit *fit);

/* True when fit a is better than fit b (higher score; near-equal scores: lower RMS). */
bool al_fit_better(const al_fit *a, const al_fit *b);

/* ---- align_egi.c ---- */

/* Up to max_out unit normals (best first, at least 12 deg apart) about which the
 * area-weighted distribution of the surface normals is most nearly
 * reflection-symmetric: candidate mirror/glide plane normals. Returns how many. */
int al_egi_mirror_normals(const al_surface *s, double (*out)[3], int max_out);

/* ---- align_axial.c / align_planar.c ---- */

/* Shared inputs of a search. */
typedef struct al_ctx {
    al_surface *surf;
    al_samples probe;      /* a few hundred samples for rough scans (plane offsets) */
    al_samples screen;     /* a few hundred samples to screen candidates */
    al_samples coarse;     /* a few thousand samples to refine candidates */
    al_samples fine;       /* ten thousand for the final refinement */
    const sr_symmetry *sym;
    const sr_align_opts *opts; /* defaults filled in */
    double tol;            /* inlier tolerance for scores, mm */
    bool have_hint;        /* opts->hint given: */
    double hint[3];        /* its unit direction */
} al_ctx;

/* Axis direction and point minimising the normal-line residuals (Pottmann & Randrup
 * 1998), iteratively reweighted. Returns false when degenerate. */
bool al_axial_normal_lines(const al_surface *s, double a[3], double c[3]);

sr_status al_axial_search(al_ctx *ctx, al_model *out, al_fit *fit);
sr_status al_planar_search(al_ctx *ctx, al_model *out, al_fit *fit);

/* ---- align_paper.c ---- */

/* Result of the paper's Algorithm 3. */
typedef struct al_paper_result {
    double dir[3];         /* axial: axis; planar: in-plane axis (the slicing z) */
    double point[3];       /* a point on the axis / in the plane */
    double normal[3];      /* planar: plane normal */
    double shift;          /* glide: shift found, mm */
    int symmetric_layers;  /* at the chosen rotation */
} al_paper_result;

/* Algorithm 3 with Algorithm 1 layers over a grid of tilts (axial) or of slicing
 * directions and in-layer plane angles (mirror, glide). */
sr_status al_paper_align(const al_surface *s, const sr_symmetry *sym,
                         const sr_align_opts *opts, al_paper_result *out);

/* Number of Alg. 3 symmetric layers of the scan in the canonical frame given by
 * xform (axial: round about the z axis; planar: mirror-symmetric about x = 0). */
int al_paper_count(const al_surface *s, const sr_symmetry *sym, const sr_align_opts *opts,
                   const double xform[12]);

#endif
