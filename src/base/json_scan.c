/*
 * json_scan.c: the members of a stored JSON object as spans of text (json_scan.h). One
 * pass, no allocation; strings are skipped with their escapes, nesting is counted.
 */
#include "base/json_scan.h"

const char *sr_json_skip_space(const char *p)
{
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
        p++;
    return p;
}

const char *sr_json_value_end(const char *p)
{
    int depth = 0;
    bool in_str = false;
    const char *q = p;
    for (; *q; q++) {
        char c = *q;
        if (in_str) {
            if (c == '\\' && q[1])
                q++;
            else if (c == '"') {
                in_str = false;
                if (depth == 0)
                    return q + 1;
            }
            continue;
        }
        if (c == '"') {
            in_str = true;
        } else if (c == '{' || c == '[') {
            depth++;
        } else if (c == '}' || c == ']') {
            if (depth == 0)
                return q == p ? NULL : q;
            if (--depth == 0)
                return q + 1;
        } else if (depth == 0 && (c == ',' || c == ' ' || c == '\n' || c == '\t' || c == '\r')) {
            return q == p ? NULL : q;
        }
    }
    return depth == 0 && !in_str && q != p ? q : NULL;
}

bool sr_json_for_members(const char *text, sr_json_member_fn fn, void *user)
{
    if (!text)
        return false;
    const char *p = sr_json_skip_space(text);
    if (*p != '{')
        return false;
    p = sr_json_skip_space(p + 1);
    while (*p == '"') {
        const char *kend = sr_json_value_end(p);
        if (!kend)
            return false;
        const char *colon = sr_json_skip_space(kend);
        if (*colon != ':')
            return false;
        const char *v = sr_json_skip_space(colon + 1);
        const char *vend = sr_json_value_end(v);
        if (!vend)
            return false;
        fn(p + 1, (size_t)(kend - p - 2), v, vend, user);
        p = sr_json_skip_space(vend);
        if (*p != ',')
            return *p == '}';
        p = sr_json_skip_space(p + 1);
    }
    return *p == '}';
}
