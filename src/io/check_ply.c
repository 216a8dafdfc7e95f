/*
 * check_ply.c: checks of a PLY file (see file_check.h): a strict header (formats ascii,
 * binary_little_endian and binary_big_endian 1.0, every line known, counts plausible
 * against the file size), then the whole body walked element by element, the vertex
 * coordinates and face lists collected and everything else stepped over.
 *
 * The shared tokenizer, numbers and messages are in check_common.c (check_int.h).
 */
#include "io/check_int.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef enum ply_type { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 } ply_type;

static const struct {
    const char *name;
    ply_type type;
} ply_type_names[] = {
    {"char", T_I8},   {"int8", T_I8},     {"uchar", T_U8},  {"uint8", T_U8},
    {"short", T_I16}, {"int16", T_I16},   {"ushort", T_U16}, {"uint16", T_U16},
    {"int", T_I32},   {"int32", T_I32},   {"uint", T_U32},  {"uint32", T_U32},
    {"float", T_F32}, {"float32", T_F32}, {"double", T_F64}, {"float64", T_F64},
};

static const size_t ply_type_size[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

static ply_type ply_type_of(const char *s, const char *e)
{
    for (size_t i = 0; i < sizeof ply_type_names / sizeof ply_type_names[0]; i++)
        if ((size_t)(e - s) == strlen(ply_type_names[i].name) &&
            memcmp(s, ply_type_names[i].name, (size_t)(e - s)) == 0)
            return ply_type_names[i].type;
    return T_NONE;
}

#define PLY_MAX_ELEMENTS 32
#define PLY_MAX_PROPS 256
#define PLY_NAME 32

typedef struct ply_prop {
    ply_type type;        /* scalar type, or the list's item type */
    ply_type count_type;  /* T_NONE for a scalar */
    char count_name[PLY_NAME];   /* the list length's type as written */
    char name[PLY_NAME];
} ply_prop;

typedef struct ply_elem {
    char name[PLY_NAME];
    unsigned long long count;
    size_t first_prop, prop_count;
} ply_elem;

enum { PLY_ASCII, PLY_LE, PLY_BE };

typedef struct ply_header {
    int format;
    size_t elem_count, prop_count;
    ply_elem elem[PLY_MAX_ELEMENTS];
    ply_prop prop[PLY_MAX_PROPS];
    size_t body;          /* offset of the first body byte */
} ply_header;

static int copy_name(char dst[PLY_NAME], const char *s, const char *e)
{
    if ((size_t)(e - s) >= PLY_NAME)
        return 0;
    memcpy(dst, s, (size_t)(e - s));
    dst[e - s] = '\0';
    return 1;
}

static sr_status ply_read_header(const unsigned char *data, size_t size, const char *name,
                                 ply_header *h, sr_err *err)
{
    fc_line_reader r = {(const char *)data, (const char *)data + size, 0};
    const char *s, *e, *p, *ts, *te;
    char tok[40];
    memset(h, 0, sizeof *h);
    h->format = -1;
    if (!fc_next_line(&r, &s, &e) || !(p = s, fc_next_token(&p, e, &ts, &te, 0)) ||
        !fc_token_eq(ts, te, "ply") || fc_next_token(&p, e, &ts, &te, 0))
        return fc_fail(err, SR_E_FORMAT, name, "not a PLY file (first line is not 'ply')");
    for (;;) {
        if (!fc_next_line(&r, &s, &e))
            return fc_fail(err, SR_E_FORMAT, name, "PLY header has no end_header");
        size_t ln = r.number;
        p = s;
        if (!fc_next_token(&p, e, &ts, &te, 0))
            return fc_fail(err, SR_E_FORMAT, name, "PLY header line %zu is blank", ln);
        if (fc_token_eq(ts, te, "comment") || fc_token_eq(ts, te, "obj_info"))
            continue;
        if (fc_token_eq(ts, te, "end_header")) {
            if (fc_next_token(&p, e, &ts, &te, 0))
                return fc_fail(err, SR_E_FORMAT, name, "PLY header line %zu: text after end_header",
                               ln);
            break;
        }
        if (fc_token_eq(ts, te, "format")) {
            const char *fs, *fe, *vs, *ve;
            if (h->format >= 0 || h->elem_count)
                return fc_fail(err, SR_E_FORMAT, name,
                               "PLY header line %zu: misplaced 'format'", ln);
            if (!fc_next_token(&p, e, &fs, &fe, 0) || !fc_next_token(&p, e, &vs, &ve, 0) ||
                fc_next_token(&p, e, &ts, &te, 0))
                return fc_fail(err, SR_E_FORMAT, name,
                               "PLY header line %zu: 'format' needs a type and a version", ln);
            if (fc_token_eq(fs, fe, "ascii"))
                h->format = PLY_ASCII;
            else if (fc_token_eq(fs, fe, "binary_little_endian"))
                h->format = PLY_LE;
            else if (fc_token_eq(fs, fe, "binary_big_endian"))
                h->format = PLY_BE;
            else
                return fc_fail(err, SR_E_FORMAT, name, "PLY header line %zu: unknown format '%s'",
                               ln, fc_token_str(fs, fe, tok));
            if (!fc_token_eq(vs, ve, "1.0"))
                return fc_fail(err, SR_E_UNSUPPORTED, name, "PLY version '%s' (only 1.0)",
                               fc_token_str(vs, ve, tok));
            continue;
        }
        if (h->format < 0)
            return fc_fail(err, SR_E_FORMAT, name, "PLY header line %zu: 'format' must come first",
                           ln);
        if (fc_token_eq(ts, te, "element")) {
            const char *ns, *ne, *cs, *ce;
            long long count;
            if (!fc_next_token(&p, e, &ns, &ne, 0) || !fc_next_token(&p, e, &cs, &ce, 0) ||
                fc_next_token(&p, e, &ts, &te, 0))
                return fc_fail(err, SR_E_FORMAT, name,
                               "PLY header line %zu: 'element' needs a name and a count", ln);
            if (*cs == '-' || *cs == '+' || !fc_parse_int(cs, ce, &count) ||
                count > (long long)UINT32_MAX)
                return fc_fail(err, SR_E_FORMAT, name,
                               "PLY header line %zu: element count '%s' is not a number", ln,
                               fc_token_str(cs, ce, tok));
            if (h->elem_count == PLY_MAX_ELEMENTS)
                return fc_fail(err, SR_E_FORMAT, name, "PLY header has more than %d elements",
                               PLY_MAX_ELEMENTS);
            ply_elem *el = &h->elem[h->elem_count];
            if (!copy_name(el->name, ns, ne))
                return fc_fail(err, SR_E_FORMAT, name, "PLY header line %zu: element name too long",
                               ln);
            for (size_t i = 0; i < h->elem_count; i++)
                if (strcmp(h->elem[i].name, el->name) == 0)
                    return fc_fail(err, SR_E_FORMAT, name, "PLY header repeats element '%s'",
                                   el->name);
            el->count = (unsigned long long)count;
            el->first_prop = h->prop_count;
            el->prop_count = 0;
            h->elem_count++;
            continue;
        }
        if (fc_token_eq(ts, te, "property")) {
            if (!h->elem_count)
                return fc_fail(err, SR_E_FORMAT, name,
                               "PLY header line %zu: 'property' before any element", ln);
            if (h->prop_count == PLY_MAX_PROPS)
                return fc_fail(err, SR_E_FORMAT, name, "PLY header has more than %d properties",
                               PLY_MAX_PROPS);
            ply_prop *pr = &h->prop[h->prop_count];
            const char *as, *ae;
            if (!fc_next_token(&p, e, &as, &ae, 0))
                return fc_fail(err, SR_E_FORMAT, name,
                               "PLY header line %zu: 'property' needs a type", ln);
            pr->count_type = T_NONE;
            if (fc_token_eq(as, ae, "list")) {
                const char *cs2, *ce2, *is, *ie;
                if (!fc_next_token(&p, e, &cs2, &ce2, 0) || !fc_next_token(&p, e, &is, &ie, 0))
                    return fc_fail(err, SR_E_FORMAT, name,
                                   "PLY header line %zu: 'property list' needs two types", ln);
                pr->count_type = ply_type_of(cs2, ce2);
                pr->type = ply_type_of(is, ie);
                if (pr->count_type != T_NONE)
                    copy_name(pr->count_name, cs2, ce2);
                if (pr->count_type == T_NONE || pr->count_type >= T_F32 || pr->type == T_NONE)
                    return fc_fail(err, SR_E_FORMAT, name,
                                   "PLY header line %zu: bad list types '%s'", ln,
                                   fc_token_str(cs2, ie, tok));
            } else {
                pr->type = ply_type_of(as, ae);
                if (pr->type == T_NONE)
                    return fc_fail(err, SR_E_FORMAT, name,
                                   "PLY header line %zu: unknown property type '%s'", ln,
                                   fc_token_str(as, ae, tok));
            }
            const char *ns, *ne;
            if (!fc_next_token(&p, e, &ns, &ne, 0))
                return fc_fail(err, SR_E_FORMAT, name,
                               "PLY header line %zu: 'property' is missing its name", ln);
            if (fc_next_token(&p, e, &ts, &te, 0))
                return fc_fail(err, SR_E_FORMAT, name,
                               "PLY header line %zu: text after the property name", ln);
            if (!copy_name(pr->name, ns, ne))
                return fc_fail(err, SR_E_FORMAT, name,
                               "PLY header line %zu: property name too long", ln);
            h->prop_count++;
            h->elem[h->elem_count - 1].prop_count++;
            continue;
        }
        return fc_fail(err, SR_E_FORMAT, name, "PLY header line %zu: unknown keyword '%s'", ln,
                       fc_token_str(ts, te, tok));
    }
    if (h->format < 0)
        return fc_fail(err, SR_E_FORMAT, name, "PLY header has no 'format' line");
    h->body = (size_t)(r.pos - (const char *)data);
    return SR_OK;
}

/* Reads the next value of a PLY body into *out and advances b->pos: 1 done, 0 the body
 * ended, -1 an ASCII token that is not a number of that type. Integers come back exactly
 * (every PLY integer type fits a double). */
typedef struct ply_body {
    const unsigned char *data;
    size_t pos, size;
    int format;
    const char *bad_s, *bad_e;   /* ASCII: the token that failed to parse */
} ply_body;

static int ply_next(ply_body *b, ply_type t, double *out)
{
    if (b->format == PLY_ASCII) {
        const char *p = (const char *)b->data + b->pos, *e = (const char *)b->data + b->size;
        while (p < e && (fc_blank((unsigned char)*p) || *p == '\n'))
            p++;
        const char *s = p;
        while (p < e && !fc_blank((unsigned char)*p) && *p != '\n')
            p++;
        if (s == p)
            return 0;
        b->bad_s = s;
        b->bad_e = p;
        if (t >= T_F32) {
            if (!fc_parse_real(s, p, out))
                return -1;
        } else {
            long long v;
            if (!fc_parse_int(s, p, &v))
                return -1;
            *out = (double)v;
        }
        b->pos = (size_t)(p - (const char *)b->data);
        return 1;
    }
    size_t n = ply_type_size[t];
    if (b->size - b->pos < n)
        return 0;
    unsigned char c[8] = {0};   /* u32 below reads four bytes of any type */
    for (size_t i = 0; i < n; i++)
        c[i] = b->data[b->pos + (b->format == PLY_LE ? i : n - 1 - i)];
    b->pos += n;
    uint32_t u32 = (uint32_t)c[0] | (uint32_t)c[1] << 8 | (uint32_t)c[2] << 16 |
                   (uint32_t)c[3] << 24;
    switch (t) {
    case T_I8: *out = (int8_t)c[0]; break;
    case T_U8: *out = c[0]; break;
    case T_I16: *out = (int16_t)(uint16_t)(c[0] | c[1] << 8); break;
    case T_U16: *out = (uint16_t)(c[0] | c[1] << 8); break;
    case T_I32: *out = (int32_t)u32; break;
    case T_U32: *out = u32; break;
    case T_F32: {
        float f;
        memcpy(&f, &u32, 4);
        *out = f;
        break;
    }
    case T_F64: {
        uint64_t u64 = (uint64_t)u32 | (uint64_t)((uint32_t)c[4] | (uint32_t)c[5] << 8 |
                                                  (uint32_t)c[6] << 16 | (uint32_t)c[7] << 24)
                                           << 32;
        double d;
        memcpy(&d, &u64, 8);
        *out = d;
        break;
    }
    default: return -1;
    }
    return 1;
}

sr_status sr_file_check_ply(const unsigned char *data, size_t size, const char *name,
                            sr_file_facts *out, sr_err *err)
{
    ply_header *h = malloc(sizeof *h);
    if (!h)
        return fc_fail(err, SR_E_NOMEM, name, "out of memory");
    sr_file_facts f = {0};
    fc_face_acc acc = {0};
    fc_corner_buf cb = {0};
    sr_status st = ply_read_header(data, size, name, h, err);
    if (st)
        goto out;
    /* Roles: x, y, z of `vertex`; the index list of `face`. */
    long vertex_el = -1, face_el = -1, face_list = -1, coord[3] = {-1, -1, -1};
    for (size_t i = 0; i < h->elem_count; i++) {
        ply_elem *el = &h->elem[i];
        if (el->count && !el->prop_count) {
            st = fc_fail(err, SR_E_FORMAT, name, "PLY element '%s' has no properties", el->name);
            goto out;
        }
        if (strcmp(el->name, "vertex") == 0) {
            vertex_el = (long)i;
            for (size_t k = 0; k < el->prop_count; k++) {
                ply_prop *pr = &h->prop[el->first_prop + k];
                static const char *const axis[3] = {"x", "y", "z"};
                for (int j = 0; j < 3; j++)
                    if (pr->count_type == T_NONE && strcmp(pr->name, axis[j]) == 0)
                        coord[j] = (long)(el->first_prop + k);
            }
        } else if (strcmp(el->name, "face") == 0) {
            face_el = (long)i;
            if (vertex_el < 0) {
                st = fc_fail(err, SR_E_UNSUPPORTED, name,
                             "PLY face element before the vertex element");
                goto out;
            }
            for (size_t k = 0; k < el->prop_count; k++) {
                ply_prop *pr = &h->prop[el->first_prop + k];
                if (pr->count_type != T_NONE && (strcmp(pr->name, "vertex_indices") == 0 ||
                                                 strcmp(pr->name, "vertex_index") == 0))
                    face_list = (long)(el->first_prop + k);
            }
            if (face_list < 0 || h->prop[face_list].type >= T_F32) {
                st = fc_fail(err, SR_E_FORMAT, name,
                             "PLY face element has no integer list 'vertex_indices'");
                goto out;
            }
            /* OpenMesh 9 knows only these names for a list length ("Unsupported Index
             * type for property list"), not even their synonyms int8 or int32. */
            const char *cn = h->prop[face_list].count_name;
            if (strcmp(cn, "uchar") != 0 && strcmp(cn, "uint8") != 0 && strcmp(cn, "int") != 0) {
                st = fc_fail(err, SR_E_UNSUPPORTED, name,
                             "PLY face list length type '%s' (OpenMesh reads uchar, uint8 or int)",
                             cn);
                goto out;
            }
        }
    }
    if (vertex_el < 0 || coord[0] < 0 || coord[1] < 0 || coord[2] < 0) {
        st = fc_fail(err, SR_E_FORMAT, name, "PLY has no vertex element with x, y and z");
        goto out;
    }
    /* Counts against the body size: the shortest row of each element. */
    size_t body = size - h->body;
    unsigned long long need = 0;
    for (size_t i = 0; i < h->elem_count; i++) {
        ply_elem *el = &h->elem[i];
        unsigned long long row = 0;
        for (size_t k = 0; k < el->prop_count; k++) {
            ply_prop *pr = &h->prop[el->first_prop + k];
            row += h->format == PLY_ASCII ? 2
                   : ply_type_size[pr->count_type != T_NONE ? pr->count_type : pr->type];
        }
        need += el->count * row;
        if (need > (unsigned long long)body + 1) {
            st = fc_fail(err, SR_E_FORMAT, name,
                         "PLY header declares %llu '%s' elements, more than the %zu-byte body "
                         "can hold", el->count, el->name, body);
            goto out;
        }
    }
    size_t nv = (size_t)h->elem[vertex_el].count;
    if (nv) {
        f.xyz = malloc(nv * 3 * sizeof *f.xyz);
        if (!f.xyz) {
            st = fc_fail(err, SR_E_NOMEM, name, "out of memory for %zu vertices", nv);
            goto out;
        }
    }
    f.vertex_count = nv;
    f.binary = h->format != PLY_ASCII;
    ply_body b = {data, h->body, size, h->format, NULL, NULL};
    for (size_t i = 0; i < h->elem_count; i++) {
        ply_elem *el = &h->elem[i];
        for (unsigned long long row = 0; row < el->count; row++) {
            int got = 1;
            for (size_t k = 0; k < el->prop_count; k++) {
                size_t pi = el->first_prop + k;
                ply_prop *pr = &h->prop[pi];
                double v;
                if (pr->count_type == T_NONE) {
                    got = ply_next(&b, pr->type, &v);
                    if (got <= 0)
                        goto body_error;
                    if ((long)i == vertex_el) {
                        for (int j = 0; j < 3; j++)
                            if ((long)pi == coord[j]) {
                                if (!isfinite(v)) {
                                    st = fc_fail(err, SR_E_INVALID, name,
                                                 "PLY vertex %llu has %s coordinate", row,
                                                 fc_nonfinite_word(v));
                                    goto out;
                                }
                                f.xyz[3 * row + j] = v;
                            }
                    }
                    continue;
                }
                got = ply_next(&b, pr->count_type, &v);
                if (got <= 0)
                    goto body_error;
                size_t item = h->format == PLY_ASCII ? 2 : ply_type_size[pr->type];
                if (v < 0 || v * (double)item > (double)(b.size - b.pos) + 1) {
                    st = fc_fail(err, SR_E_FORMAT, name, "PLY %s %llu has a bad list length %.0f",
                                 el->name, row, v);
                    goto out;
                }
                size_t n = (size_t)v;
                int is_face = (long)pi == face_list;
                if (is_face && n < 3) {
                    st = fc_fail(err, SR_E_FORMAT, name, "PLY face %llu has %zu vertices", row, n);
                    goto out;
                }
                if (is_face && !fc_grow((void **)&cb.v, &cb.cap, n, sizeof *cb.v)) {
                    st = fc_fail(err, SR_E_NOMEM, name, "out of memory at face %llu", row);
                    goto out;
                }
                for (size_t c = 0; c < n; c++) {
                    got = ply_next(&b, pr->type, &v);
                    if (got <= 0)
                        goto body_error;
                    if (is_face) {
                        if (!(v >= 0 && v < (double)nv)) {
                            st = fc_fail(err, SR_E_INVALID, name,
                                         "PLY face %llu uses vertex %.0f, file has %zu", row,
                                         v, nv);
                            goto out;
                        }
                        cb.v[c] = (uint32_t)v;
                    }
                }
                if (is_face && !fc_add_face(&f, &acc, cb.v, n)) {
                    st = fc_fail(err, SR_E_NOMEM, name, "out of memory at face %llu", row);
                    goto out;
                }
            }
            continue;
        body_error:
            if (got == 0) {
                st = fc_fail(err, SR_E_FORMAT, name, "PLY body ends inside %s %llu of %llu",
                             el->name, row, el->count);
            } else {
                char tok[40];
                st = fc_fail(err, SR_E_FORMAT, name, "PLY %s %llu: bad value '%s'", el->name, row,
                             fc_token_str(b.bad_s, b.bad_e, tok));
            }
            goto out;
        }
    }
    if (h->format == PLY_ASCII) {
        for (size_t i = b.pos; i < size; i++)
            if (!fc_blank(data[i]) && data[i] != '\n') {
                st = fc_fail(err, SR_E_FORMAT, name, "text after the last PLY element (offset %zu)",
                             i);
                goto out;
            }
    } else if (b.pos < size) {
        st = fc_fail(err, SR_E_FORMAT, name, "%zu bytes after the last PLY element", size - b.pos);
        goto out;
    }
    (void)face_el;
    free(cb.v);
    free(h);
    *out = f;
    return SR_OK;
out:
    free(cb.v);
    free(h);
    sr_file_facts_release(&f);
    return st;
}
