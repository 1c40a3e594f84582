/* fma_clones.h -- private to libparaxial: the fused 3-vector functions of paraxial/vec3.h for its
 * per-ray code (px_interface_outgoing, the vector form of Snell's law, section 2.2), and the
 * clone attribute below. The exported px_vec3_* functions in linalg.c are the same functions,
 * so results are the same bit for bit.
 *
 * PX_FMA_CLONES marks a per-ray function to be compiled twice, for any x86-64 and for CPUs with
 * FMA instructions, the loader picking one (GCC/Clang target_clones, a glibc ifunc). fma() is
 * correctly rounded either way and the library is built with -ffp-contract=off, so the clones
 * compute identical results; the FMA clone only replaces each libm fma() call by an instruction.
 * The binary still runs on any x86-64. */
#ifndef PARAXIAL_FMA_CLONES_H
#define PARAXIAL_FMA_CLONES_H

#include <math.h>

#include "paraxial/linalg.h"
#include "paraxial/vec3.h"

#ifndef PX_FMA_CLONES /* -DPX_FMA_CLONES= builds without clones, e.g. to compare results */
/* Clang before 16 names the dispatching ifunc "NAME.ifunc", not NAME, so calls from other files
 * do not link (found by the clang fuzz build); it gets no clones, with the same results. */
#if defined(__clang__) && __clang_major__ < 16
#define PX_FMA_CLONES
#elif defined(__x86_64__) && defined(__linux__) && defined(__has_attribute)
#if __has_attribute(target_clones)
#define PX_FMA_CLONES __attribute__((target_clones("fma", "default")))
#endif
#endif
#endif
#ifndef PX_FMA_CLONES
#define PX_FMA_CLONES
#endif

#endif
