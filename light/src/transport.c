/* transport.c -- one light ray through the scene: at every surface the same reflected and
 * refracted children as the renderers' rays (rt_shade_children: kr, kt T, Fresnel, total
 * internal reflection, the depth limit), their weights multiplied along the path; a path that
 * meets the receiver is recorded there, and goes on if the receiver itself reflects or
 * transmits. Opaque surfaces end a path. For a caustic map (lt_ctx_t.indirect) a ray that meets
 * the receiver first is not recorded there. */
#include <math.h>

#include "core/intersect.h"
#include "internal.h"

static uint64_t mix(uint64_t h, uint64_t x) {
  h ^= x + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  h *= 0xff51afd7ed558ccdull;
  return h ^ (h >> 33);
}

static void end(lt_ctx_t *C, lt_arrivals_t *out, uint64_t sig, int kind, double u, double v,
                rt_rgb_t w) {
  if (out->n < LT_MAX_ARRIVALS)
    out->a[out->n++] = (lt_arrival_t){mix(sig, 0xe0u + (uint64_t)kind), kind, u, v, w};
  else
    C->st.lost++;
}

static void trace(lt_ctx_t *C, const rt_ray_t *ray, rt_rgb_t w, int depth, uint64_t sig,
                  lt_arrivals_t *out) {
  C->st.segments++;
  rt_hit_t hit;
  if (!rt_intersect(C->s, ray, &hit)) {
    end(C, out, sig, LT_END_ESCAPED, 0, 0, w);
    return;
  }
  sig = mix(mix(sig, (uint64_t)(uint32_t)hit.object), (uint64_t)(uint32_t)hit.prim);
  for (int k = 0; k < C->r->n && !(C->indirect && depth == 0); k++)
    if (hit.object == C->r->object[k]) {
      px_vec3_t d = px_v3_sub(hit.p, C->r->p);
      end(C, out, sig, LT_END_RECEIVER, px_v3_dot(d, C->r->u), px_v3_dot(d, C->r->v), w);
      break;
    }
  rt_surface_t sf;
  rt_shade_surface(C->s, &hit, ray, &sf);
  rt_child_t ch[2];
  int n = rt_shade_children(C->s, &C->plan, &sf, ray, depth, ch);
  rt_rgb_t kept = rt_rgb(1, 1, 1);
  for (int k = 0; k < n; k++)
    kept = rt_rgb(kept.r - ch[k].weight.r, kept.g - ch[k].weight.g, kept.b - ch[k].weight.b);
  kept = rt_rgb(fmax(kept.r, 0.0), fmax(kept.g, 0.0), fmax(kept.b, 0.0));
  if (kept.r + kept.g + kept.b > 0)
    end(C, out, sig, LT_END_ABSORBED, 0, 0, rt_rgb_mul(w, kept));
  for (int k = 0; k < n; k++)
    trace(C, &ch[k].ray, rt_rgb_mul(w, ch[k].weight), depth + 1, mix(sig, ch[k].kind + 1u), out);
}

void lt__trace(lt_ctx_t *C, const rt_ray_t *ray, lt_arrivals_t *out) {
  out->n = 0;
  C->st.rays++;
  trace(C, ray, rt_rgb(1, 1, 1), 0, 0x5eed, out);
  for (int k = 0; k < out->n; k++)
    C->st.arrivals += out->a[k].kind == LT_END_RECEIVER;
}

void lt__trace_from(lt_ctx_t *C, const rt_ray_t *ray, rt_rgb_t w, int depth, lt_arrivals_t *out) {
  out->n = 0;
  C->st.rays++;
  trace(C, ray, w, depth, 0x5eed, out);
  for (int k = 0; k < out->n; k++)
    C->st.arrivals += out->a[k].kind == LT_END_RECEIVER;
}
