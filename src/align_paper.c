/* stub */
#include "align_internal.h"
sr_status al_paper_align(const al_surface *s, const sr_symmetry *sym,
                         const sr_align_opts *opts, al_paper_result *out) { (void)s;(void)sym;(void)opts;(void)out; return SR_E_UNSUPPORTED; }
int al_paper_count_axial(const al_surface *s, const sr_align_opts *opts, const double dir[3],
                         const double point[3]) { return 0; }
