/* lane_scalar.h — the contact formulas of law_body.h for one contact at a time
 * (doubles): the general path's force loop, the fast wall pass, the ODE methods. Their
 * names end in _s (esf_law_tangential_s). */
#ifndef ESF_LANE_SCALAR_H
#define ESF_LANE_SCALAR_H

#include <math.h>

#define LANE_R            double
#define LANE_M            int
#define LANE_SEL(m, a, b) ((m) ? (a) : (b))
#define LANE_SQRT(x)      sqrt(x)
#define LANE_ANY(m)       (m)
#define LANE_POW(x, y)    pow(x, y)
#define LANE_FN(name)     name##_s
#define LANE_INLINE       static inline
#include "contact/law_body.h"
#undef LANE_R
#undef LANE_M
#undef LANE_SEL
#undef LANE_SQRT
#undef LANE_ANY
#undef LANE_POW
#undef LANE_FN
#undef LANE_INLINE

#endif
