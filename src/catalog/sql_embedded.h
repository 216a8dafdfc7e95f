/*
 * sql_embedded.h: the files of sql/, compiled into the binary by the Makefile
 * (build/<config>/gen/sql_embedded.c), so a catalogue can be created and migrated
 * without the source tree. Fetched by name; the table ends with { NULL, NULL }.
 */
#ifndef SR_SQL_EMBEDDED_H
#define SR_SQL_EMBEDDED_H

typedef struct sr_sql_file {
    const char *name;   /* file name, e.g. "001_init.sql" */
    const char *text;   /* its whole text */
} sr_sql_file;

extern const sr_sql_file sr_sql_files[];

#endif
