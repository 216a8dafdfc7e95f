/*
 * report_assets.h: the HTML report's stylesheet and script, src/report/report.css and
 * report.js, compiled into the binary by the Makefile (build/<config>/gen/
 * report_assets.c), so a report can be written without the source tree. Each is the
 * file's text without its opening comment; the stylesheet's lines are joined without
 * newlines (the page carries it as one line), the script's kept.
 */
#ifndef SR_REPORT_ASSETS_H
#define SR_REPORT_ASSETS_H

extern const char sr_report_css[];   /* NUL-terminated */
extern const char sr_report_js[];    /* NUL-terminated */

#endif
