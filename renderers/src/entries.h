/* entries.h -- the entries of the renderer table (private): one per file of renderers/src. */
#ifndef RENDERERS_ENTRIES_H
#define RENDERERS_ENTRIES_H

#include "renderers/renderer.h"

/** The exact (Whitted) reference renderer (exact.c). */
extern const rn_renderer_t rn_exact_entry;
/** The pencil renderer of the 1987 paper's section 4.1 (pencil.c). */
extern const rn_renderer_t rn_pencil_entry;

#endif
