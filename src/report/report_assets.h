/*
 * report_assets.h: the HTML report's stylesheet and scripts, src/report/report.css,
 * report.js and report_view.js, compiled into the binary by the Makefile (build/<config>/gen/
 * report_assets.c), so a report can be written without the source tree. Each is the
 * file's text without its opening comment; the stylesheet's lines are joined without
 * newlines (the page carries it as one line), the scripts' kept.
 *
 * sr_report_three_js is three.js (three.min.js of Debian's libjs-three, r111, MIT
 * licence), compiled in byte for byte by the Makefile (build/<config>/gen/
 * report_three.c), the 3D view's renderer; the build refuses a file that holds
 * '</script' (it could not be carried inside the page's <script> element).
 */
#ifndef SR_REPORT_ASSETS_H
#define SR_REPORT_ASSETS_H

extern const char sr_report_css[];   /* NUL-terminated */
extern const char sr_report_js[];    /* NUL-terminated */
extern const char sr_report_view_js[];  /* NUL-terminated */
extern const char sr_report_three_js[]; /* NUL-terminated */

#endif
