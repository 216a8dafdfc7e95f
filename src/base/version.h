/*
 * version.h: the one place symrec's version string lives (printed by `symrec --version`
 * and stored with every reconstruction run).
 */
#ifndef SR_VERSION_H
#define SR_VERSION_H

#define SR_VERSION "0.1.0"

#endif
