/* table.c -- the renderer table (renderer.h) and the helpers that read its option records.
 * A new renderer adds its entry to `table` below and its file to renderers/CMakeLists.txt. */
#include "renderers/renderer.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "entries.h"

static const rn_renderer_t *const table[] = {&rn_exact_entry, &rn_pencil_entry, &rn_beam_entry};

int rn_count(void) {
  return (int)(sizeof table / sizeof table[0]);
}

const rn_renderer_t *rn_entry(int k) {
  return k >= 0 && k < rn_count() ? table[k] : NULL;
}

const rn_renderer_t *rn_find(const char *name) {
  for (int k = 0; k < rn_count(); k++)
    if (strcmp(table[k]->name, name) == 0)
      return table[k];
  return NULL;
}

rt_plan_t rn_plan_make(const rn_renderer_t *r, const rt_scene_t *s, int spp, const void *options) {
  rt_plan_t p = rt_plan_make(s, spp);
  if (!r->dispersion) {
    char why[80];
    snprintf(why, sizeof why, "the %s renderer does not draw dispersion yet", r->name);
    rt_plan_no_dispersion(&p, s, why);
  }
  if (r->adapt_plan)
    r->adapt_plan(&p, s, options ? options : r->defaults);
  return p;
}

const rn_renderer_t *rn_exact(void) {
  return &rn_exact_entry;
}

const rn_option_t *rn_option_find(const rn_renderer_t *r, const char *name) {
  for (int k = 0; k < r->noptions; k++)
    if (strcmp(r->options[k].name, name) == 0)
      return &r->options[k];
  return NULL;
}

void rn_defaults(const rn_renderer_t *r, void *options) {
  memcpy(options, r->defaults, r->options_size);
}

/* The "expected ..." phrase of a numeric option: "a number > 0", "an integer from 1 to 32". */
static void expected(const rn_option_t *o, char *buf, size_t cap) {
  if (o->kind == RN_OPT_INT)
    snprintf(buf, cap, "an integer from %.0f to %.0f", o->lo, o->hi);
  else if (isinf(o->hi))
    snprintf(buf, cap, "a number %s %g", o->lo_open ? ">" : ">=", o->lo);
  else
    snprintf(buf, cap, "a number %s %g and <= %g", o->lo_open ? ">" : ">=", o->lo, o->hi);
}

int rn_parse_double(const char *text, double *out) {
  const char *p = text;
  int digits = 0;
  p += *p == '-'; /* no '+': one way to write a number, as rn_parse_long() */
  for (; *p >= '0' && *p <= '9'; p++)
    digits++;
  if (*p == '.')
    for (p++; *p >= '0' && *p <= '9'; p++)
      digits++;
  if (digits > 0 && (*p == 'e' || *p == 'E')) {
    p++;
    p += *p == '+' || *p == '-';
    if (!(*p >= '0' && *p <= '9'))
      return 0;
    while (*p >= '0' && *p <= '9')
      p++;
  }
  if (digits == 0 || *p != '\0')
    return 0;
  errno = 0;
  double v = strtod(text, NULL);
  if (errno == ERANGE && fabs(v) > 1.0) /* overflow; underflow keeps its subnormal or zero */
    return -1;
  *out = v;
  return 1;
}

int rn_parse_long(const char *text, long *out) {
  const char *p = text + (*text == '-');
  if (!*p)
    return 0;
  for (; *p; p++)
    if (*p < '0' || *p > '9')
      return 0;
  errno = 0;
  long v = strtol(text, NULL, 10);
  if (errno == ERANGE)
    return -1;
  *out = v;
  return 1;
}

/* A decimal integer (rn_parse_long()) as a double. */
static int parse_int(const char *text, double *out) {
  long v;
  if (rn_parse_long(text, &v) != 1)
    return 0;
  *out = (double)v;
  return 1;
}

static int set_number(const rn_option_t *o, void *field, const char *text, char *err, size_t cap) {
  char want[96];
  double v = 0.0;
  int ok = (o->kind == RN_OPT_INT ? parse_int(text, &v) : rn_parse_double(text, &v) == 1) &&
           (o->lo_open ? v > o->lo : v >= o->lo) && v <= o->hi;
  if (!ok) {
    expected(o, want, sizeof want);
    snprintf(err, cap, "%s: expected %s, got '%s'", o->name, want, text);
    return 0;
  }
  if (o->kind == RN_OPT_INT)
    *(int *)field = (int)v;
  else
    *(double *)field = v;
  return 1;
}

static int set_choice(const rn_option_t *o, void *field, const char *text, char *err, size_t cap) {
  for (int k = 0; o->choices[k]; k++)
    if (strcmp(o->choices[k], text) == 0) {
      *(int *)field = k;
      return 1;
    }
  size_t n = (size_t)snprintf(err, cap, "%s: expected ", o->name);
  for (int k = 0; o->choices[k] && n < cap; k++)
    n += (size_t)snprintf(err + n, cap - n, "%s%s",
                          k == 0              ? ""
                          : o->choices[k + 1] ? ", "
                                              : " or ",
                          o->choices[k]);
  if (n < cap)
    snprintf(err + n, cap - n, ", got '%s'", text);
  return 0;
}

int rn_option_set(const rn_option_t *o, void *options, const char *text, char *err, size_t cap) {
  void *field = (char *)options + o->offset;
  if (o->kind == RN_OPT_FLAG) {
    if (text) {
      snprintf(err, cap, "%s takes no value, got '%s'", o->name, text);
      return 0;
    }
    *(int *)field = o->flag_value;
    return 1;
  }
  if (!text) {
    snprintf(err, cap, "%s needs a value", o->name);
    return 0;
  }
  return o->kind == RN_OPT_CHOICE ? set_choice(o, field, text, err, cap)
                                  : set_number(o, field, text, err, cap);
}

int rn_set(const rn_renderer_t *r, void *options, const char *name, const char *text, char *err,
           size_t cap) {
  const rn_option_t *o = rn_option_find(r, name);
  if (!o) {
    snprintf(err, cap, "the %s renderer has no option %s", r->name, name);
    return 0;
  }
  return rn_option_set(o, options, text, err, cap);
}

int rn_option_idle(const rn_renderer_t *r, const void *options, const char *name, char *err,
                   size_t cap) {
  for (int k = 0; k < r->nneeds; k++) {
    const rn_needs_t *d = &r->needs[k];
    const rn_option_t *on = rn_option_find(r, d->on);
    if (strcmp(d->option, name) != 0 || !on)
      continue;
    int v = *(const int *)((const char *)options + on->offset);
    if (v >= 0 && v < 32 && (d->values >> v & 1u))
      continue;
    if (on->kind == RN_OPT_CHOICE)
      snprintf(err, cap, "%s has no effect with %s %s (only with %s)", name, on->name,
               on->choices[v], d->when);
    else
      snprintf(err, cap, "%s has no effect with %s (only with %s)", name, on->name, d->when);
    return 1;
  }
  return 0;
}

void rn_print_options(FILE *f, const rn_renderer_t *r, int indent) {
  for (int k = 0; k < r->noptions; k++) {
    const rn_option_t *o = &r->options[k];
    char head[64];
    snprintf(head, sizeof head, "%s%s%s", o->name, o->metavar ? " " : "",
             o->metavar ? o->metavar : "");
    int col = 22, wide = (int)strlen(head) > col - 2;
    fprintf(f, "%*s%-*s", indent, "", col, head);
    if (wide)
      fprintf(f, "\n%*s", indent + col, "");
    for (const char *t = o->help; *t; t++) { /* continuation lines stay in the second column */
      fputc(*t, f);
      if (*t == '\n')
        fprintf(f, "%*s", indent + col, "");
    }
    fputc('\n', f);
  }
}

int rn_image_nonfinite(const rt_image_t *img, int *x, int *y, int *channel) {
  size_t n = (size_t)img->width * (size_t)img->height;
  for (size_t k = 0; k < n; k++)
    for (int c = 0; c < 3; c++)
      if (!isfinite(img->ch[RT_CH_R + c][k])) {
        *x = (int)(k % (size_t)img->width);
        *y = (int)(k / (size_t)img->width);
        *channel = c;
        return 1;
      }
  return 0;
}

size_t rn_memory_estimate(const rn_renderer_t *r, const rt_plan_t *plan, const rn_common_t *common,
                          const void *options, int width, int height, int with_sample_errors) {
  double px = (double)width * (double)height, spp = (double)common->spp_side * common->spp_side;
  int spectral = common->aux && rt_plan_has(plan, RT_EFFECT_DISPERSION);     /* its plane */
  double bytes = px * (4.0 * (RT_CH_COUNT + r->nchannels + spectral) + 3.0); /* planes, preview */
  if (with_sample_errors)
    bytes += px * 4.0 * spp;
  if (r->thread_bytes)
    bytes +=
        (double)rt_thread_count(common->threads) * (double)r->thread_bytes(plan, common, options);
  if (r->image_bytes)
    bytes += (double)r->image_bytes(plan, common, options, width, height);
  return bytes >= (double)SIZE_MAX ? SIZE_MAX : (size_t)bytes;
}

rt_status_t rn_channels_alloc(const rn_renderer_t *r, int width, int height, rn_output_t *out) {
  size_t n = (size_t)width * (size_t)height;
  for (int k = 0; k < RN_MAX_CHANNELS; k++)
    out->channels[k] = NULL;
  for (int k = 0; k < r->nchannels; k++)
    if (!(out->channels[k] = calloc(n, sizeof(float)))) { /* zero: a channel a render leaves */
      rn_channels_free(out);
      return RT_ENOMEM;
    }
  return RT_OK;
}

void rn_channels_free(rn_output_t *out) {
  for (int k = 0; k < RN_MAX_CHANNELS; k++) {
    free(out->channels[k]);
    out->channels[k] = NULL;
  }
}
