/*
 * truth.c: reads the handful of numbers the accuracy test and the benchmark need from
 * a shared part's truth.json (see truth.h), by searching for each quoted key and
 * parsing the number or number list after its colon; and measures a found alignment
 * against the part's pose. The found element is taken from the alignment's transform
 * (the thing the pipeline actually applies), not from its descriptive fields.
 */
#include "support/truth.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bridge/boolean.h"

/* Whole file as a NUL-terminated string, or NULL. */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *buf = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (cap - len < 4096) {
            cap = cap ? 2 * cap : 65536;
            char *nb = realloc(buf, cap + 1);
            if (!nb) {
                free(buf);
                fclose(f);
                return NULL;
            }
            buf = nb;
        }
        size_t n = fread(buf + len, 1, cap - len, f);
        len += n;
        if (n == 0)
            break;
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        free(buf);
        return NULL;
    }
    buf[len] = '\0';
    return buf;
}

/* Pointer just after the colon following the first occurrence of "key", or NULL. */
static const char *value_of(const char *text, const char *key)
{
    char pat[128];
    snprintf(pat, sizeof pat, "\"%s\"", key);
    const char *p = strstr(text, pat);
    if (!p)
        return NULL;
    p += strlen(pat);
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
        p++;
    return *p == ':' ? p + 1 : NULL;
}

/* Parses `count` numbers after the key, skipping whitespace, brackets and commas. */
static int numbers_of(const char *text, const char *key, double *out, size_t count)
{
    const char *p = value_of(text, key);
    if (!p)
        return 0;
    for (size_t i = 0; i < count; i++) {
        while (*p && strchr(" \t\r\n[],", *p))
            p++;
        char *end;
        errno = 0;
        double v = strtod(p, &end);
        if (end == p || errno != 0 || !isfinite(v))
            return 0;
        out[i] = v;
        p = end;
    }
    return 1;
}

/* The string value of a key into buf, or 0. */
static int string_of(const char *text, const char *key, char *buf, size_t size)
{
    const char *p = value_of(text, key);
    if (!p)
        return 0;
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
        p++;
    if (*p != '"')
        return 0;
    p++;
    const char *q = strchr(p, '"');
    if (!q || (size_t)(q - p) >= size)
        return 0;
    memcpy(buf, p, (size_t)(q - p));
    buf[q - p] = '\0';
    return 1;
}

sr_status sr_truth_read(const char *path, sr_truth *out, sr_err *err)
{
    char *text = slurp(path);
    if (!text)
        return sr_err_set(err, SR_E_IO, "cannot read '%s': %s", path, strerror(errno));
    sr_truth t;
    memset(&t, 0, sizeof t);
    const char *bad = NULL;
    char kind[32];
    double order = 0;
    if (!string_of(text, "name", t.name, sizeof t.name))
        bad = "name";
    else if (!string_of(text, "symmetry", kind, sizeof kind) ||
             sr_sym_kind_parse(kind, "symmetry", &t.symmetry.kind, NULL) != SR_OK)
        bad = "symmetry";
    else if (!numbers_of(text, "intact_volume", &t.intact_volume, 1))
        bad = "intact_volume";
    else if (!numbers_of(text, "missing_volume", &t.missing_volume, 1))
        bad = "missing_volume";
    else if (!numbers_of(text, "rotation_matrix_3x3", t.R, 9))
        bad = "pose.rotation_matrix_3x3";
    else if (!numbers_of(text, "translation", t.t, 3))
        bad = "pose.translation";
    else if (value_of(text, "order") && !numbers_of(text, "order", &order, 1))
        bad = "order";
    else if (t.symmetry.kind == SR_SYM_GLIDE &&
             !numbers_of(text, "glide_shift_mm", &t.symmetry.shift_mm, 1))
        bad = "glide_shift_mm";
    free(text);
    if (bad)
        return sr_err_set(err, SR_E_FORMAT, "cannot read '%s': no valid '%s'", path, bad);
    t.symmetry.order = (int)order;
    *out = t;
    return SR_OK;
}

void sr_truth_to_canonical(const sr_truth *truth, double m[12])
{
    const double *R = truth->R, *t = truth->t;
    for (int i = 0; i < 3; i++) {
        /* row i of R^T is column i of R */
        m[4 * i + 0] = R[0 * 3 + i];
        m[4 * i + 1] = R[1 * 3 + i];
        m[4 * i + 2] = R[2 * 3 + i];
        m[4 * i + 3] = -(R[0 * 3 + i] * t[0] + R[1 * 3 + i] * t[1] + R[2 * 3 + i] * t[2]);
    }
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Angle between two lines (directions, sign ignored), degrees. */
static double line_angle_deg(const double a[3], const double b[3])
{
    double c = fabs(dot3(a, b)) / sqrt(dot3(a, a) * dot3(b, b));
    if (c > 1)
        c = 1;
    return acos(c) * 180.0 / M_PI;
}

void sr_truth_align_error_of(const sr_truth *truth, const sr_alignment *found,
                             const double centre[3], sr_truth_align_error *out)
{
    /* found canonical frame in the scan frame: inverse of scan -> canonical */
    double inv[12];
    sr_xform_rigid_inverse(inv, found->xform);
    double f_origin[3] = {inv[3], inv[7], inv[11]};
    double f_x[3] = {inv[0], inv[4], inv[8]};
    double f_z[3] = {inv[2], inv[6], inv[10]};
    /* true canonical axes in the posed frame: columns of R */
    const double *R = truth->R;
    double t_x[3] = {R[0], R[3], R[6]};
    double t_z[3] = {R[2], R[5], R[8]};
    const double *t_origin = truth->t;
    double d[3] = {centre[0] - t_origin[0], centre[1] - t_origin[1], centre[2] - t_origin[2]};

    if (truth->symmetry.kind == SR_SYM_AXIAL) {
        out->angle_deg = line_angle_deg(f_z, t_z);
        /* true axis point nearest the centre */
        double s = dot3(d, t_z);
        double q[3] = {t_origin[0] + s * t_z[0], t_origin[1] + s * t_z[1],
                       t_origin[2] + s * t_z[2]};
        double e[3] = {q[0] - f_origin[0], q[1] - f_origin[1], q[2] - f_origin[2]};
        double nz = sqrt(dot3(f_z, f_z));
        double along = dot3(e, f_z) / nz;
        double perp2 = dot3(e, e) - along * along;
        out->offset_mm = sqrt(perp2 > 0 ? perp2 : 0);
    } else {
        out->angle_deg = line_angle_deg(f_x, t_x);
        /* true plane point nearest the centre */
        double s = dot3(d, t_x);
        double q[3] = {centre[0] - s * t_x[0], centre[1] - s * t_x[1], centre[2] - s * t_x[2]};
        double e[3] = {q[0] - f_origin[0], q[1] - f_origin[1], q[2] - f_origin[2]};
        out->offset_mm = fabs(dot3(e, f_x)) / sqrt(dot3(f_x, f_x));
    }
}

sr_status sr_truth_patch_overlap(const sr_section *sections, size_t count, const double m[12],
                                 const sr_mesh *intact, const sr_mesh *missing,
                                 double *outside, double *covered, sr_err *err)
{
    double inv[12], out = 0, in = 0;
    sr_xform_rigid_inverse(inv, m);
    sr_mesh i_scan = {0}, m_scan = {0};
    sr_status st = sr_mesh_copy(&i_scan, intact);
    if (st == SR_OK)
        st = sr_mesh_copy(&m_scan, missing);
    if (st != SR_OK) {
        sr_mesh_release(&i_scan);
        return sr_err_set(err, st, "out of memory copying the truth meshes");
    }
    sr_mesh_transform(&i_scan, inv);
    sr_mesh_transform(&m_scan, inv);
    for (size_t k = 0; k < count && st == SR_OK; k++) {
        sr_mesh d = {0}, x = {0};
        st = sr_boolean_difference(&sections[k].patch, &i_scan, &d, err);
        if (st == SR_OK)
            st = sr_boolean_intersection(&sections[k].patch, &m_scan, &x, err);
        if (st == SR_OK) {
            out += sr_mesh_volume(&d);
            in += sr_mesh_volume(&x);
        }
        sr_mesh_release(&d);
        sr_mesh_release(&x);
    }
    sr_mesh_release(&i_scan);
    sr_mesh_release(&m_scan);
    if (st != SR_OK)
        return st;
    *outside = out;
    *covered = in;
    return SR_OK;
}
