/* src/field/field_internal.h - what the material module uses of the field module beyond
 * hovox/field.h. */
#ifndef HOVOX_FIELD_INTERNAL_H
#define HOVOX_FIELD_INTERNAL_H

#include "hovox/field.h"

/* hv_edt with out[v] = max(distance - less, 0) (less finite and >= 0; 0 gives hv_edt's
 * distances): the offset and the clamp are applied in the last pass, where the square roots are
 * taken, instead of in a sweep of their own over the box. */
hv_status hv_edt_less(const uint8_t *feature, const int64_t dims[3], const double spacing[3], float less,
                      float *out, const hv_progress *progress);

#endif
