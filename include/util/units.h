/* units.h - unit conversions: the only place their factors are written. */
#ifndef SUNMC_UNITS_H
#define SUNMC_UNITS_H

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define RAD_PER_DEG (M_PI / 180.0)
#define DEG_PER_RAD (180.0 / M_PI)
#define ARCSEC_PER_DEG 3600.0
#define RAD_PER_ARCSEC (M_PI / (180.0 * 3600.0))
#define ARCSEC_PER_RAD (180.0 * 3600.0 / M_PI)
#define MM_PER_UM 1e-3
#define UM_PER_MM 1e3
#define MM_PER_NM 1e-6
#define FRACTION_PER_PCT 1e-2

#endif
