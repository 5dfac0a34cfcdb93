/* registry.h - the sensor families sunmc knows.
 *
 * One table, sensor_families[] in registry.c: the only place in core that
 * names a family.  sensor.family's choices, names and defaults come from it;
 * everything else reaches a family through its sensor_family struct
 * (family.h), found by name here or held by the config (sunmc_config.family).
 */
#ifndef SUNMC_REGISTRY_H
#define SUNMC_REGISTRY_H

#include "family.h"

/* Number of registered families; family i (0 <= i < count), in table order.
 * Family 0 is the default of sensor.family. */
int sensor_family_count(void);
const sensor_family *sensor_family_at(int i);

/* The family named `name`; NULL when none is. */
const sensor_family *sensor_family_find(const char *name);

/* Tests only: register one more family (a test-only sensor) after the
 * built-in ones.  Not thread-safe; call before building a config.  Returns
 * 0, or -1 when the table is full or the name is taken. */
int sensor_family_register(const sensor_family *f);

#endif
