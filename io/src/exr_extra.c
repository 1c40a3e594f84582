/* exr_extra.c -- OpenEXR output of a render with extra per-pixel channels beside the renderer's
 * (the pencil renderer's per-pixel error and method, paper section 5, Fig. 10), through
 * OpenEXRCore's C API: one scanline part, float32, ZIP. Kept apart from exr.c so that the
 * reference renderer's writer is unchanged. */
#include <openexr.h>
#include <stdio.h>
#include <string.h>

#include "io/image_io.h"

typedef struct {
  char msg[256];
} xerr_t;

static void on_error(exr_const_context_t ctx, exr_result_t code, const char *msg) {
  void *ud = NULL;
  if (exr_get_user_data(ctx, &ud) == EXR_ERR_SUCCESS && ud)
    snprintf(((xerr_t *)ud)->msg, sizeof((xerr_t *)ud)->msg, "%s (%s)", msg ? msg : "error",
             exr_get_error_code_as_string(code));
}

typedef struct {
  const rt_image_t *img;
  const io_exr_channel_t *extra;
  int nextra;
} chans_t;

static const float *find(const chans_t *c, const char *name) {
  for (int k = 0; k < RT_CH_COUNT; k++)
    if (strcmp(rt_channel_name((rt_channel_t)k), name) == 0)
      return c->img->ch[k];
  for (int k = 0; k < c->nextra; k++)
    if (strcmp(c->extra[k].name, name) == 0)
      return c->extra[k].data;
  return NULL;
}

static exr_result_t define(exr_context_t ctx, const chans_t *c, const char *const (*meta)[2],
                           int nmeta) {
  int part;
  exr_result_t rv = exr_add_part(ctx, "render", EXR_STORAGE_SCANLINE, &part);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_initialize_required_attr_simple(ctx, part, c->img->width, c->img->height,
                                             EXR_COMPRESSION_ZIP);
  for (int k = 0; k < RT_CH_COUNT && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_add_channel(ctx, part, rt_channel_name((rt_channel_t)k), EXR_PIXEL_FLOAT,
                         EXR_PERCEPTUALLY_LINEAR, 1, 1);
  for (int k = 0; k < c->nextra && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_add_channel(ctx, part, c->extra[k].name, EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1,
                         1);
  for (int k = 0; k < nmeta && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_attr_set_string(ctx, part, meta[k][0], meta[k][1]);
  return rv;
}

static exr_result_t chunks(exr_context_t ctx, const chans_t *c) {
  int32_t lines;
  int width = c->img->width;
  exr_result_t rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int started = 0;
  for (int y = 0; y < c->img->height && rv == EXR_ERR_SUCCESS; y += lines) {
    exr_chunk_info_t ci;
    rv = exr_write_scanline_chunk_info(ctx, 0, y, &ci);
    if (rv == EXR_ERR_SUCCESS)
      rv = started ? exr_encoding_update(ctx, 0, &ci, &enc)
                   : exr_encoding_initialize(ctx, 0, &ci, &enc);
    if (rv != EXR_ERR_SUCCESS)
      break;
    for (int k = 0; k < enc.channel_count; k++) {
      exr_coding_channel_info_t *ch = &enc.channels[k];
      ch->user_bytes_per_element = 4;
      ch->user_data_type = EXR_PIXEL_FLOAT;
      ch->user_pixel_stride = 4;
      ch->user_line_stride = 4 * width;
      ch->encode_from_ptr = (const uint8_t *)(find(c, ch->channel_name) + (size_t)y * width);
    }
    if (!started)
      rv = exr_encoding_choose_default_routines(ctx, 0, &enc);
    started = 1;
    if (rv == EXR_ERR_SUCCESS)
      rv = exr_encoding_run(ctx, 0, &enc);
  }
  if (started)
    exr_encoding_destroy(ctx, &enc);
  return rv;
}

int io_exr_write_extra(const char *path, const rt_image_t *img, const io_exr_channel_t *extra,
                       int nextra, const char *const (*meta)[2], int nmeta, char *err, size_t cap) {
  chans_t c = {img, extra, nextra};
  for (int k = 0; k < nextra; k++)
    if (!extra[k].data || !extra[k].name || find(&c, extra[k].name) != extra[k].data) {
      snprintf(err, cap, "%s: extra channel %d is missing or duplicates a name", path, k);
      return -1;
    }
  xerr_t e = {""};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = on_error;
  init.user_data = &e;
  exr_context_t ctx = NULL;
  exr_result_t rv = exr_start_write(&ctx, path, EXR_INTERMEDIATE_TEMP_FILE, &init);
  if (rv == EXR_ERR_SUCCESS) {
    rv = define(ctx, &c, meta, nmeta);
    if (rv == EXR_ERR_SUCCESS)
      rv = exr_write_header(ctx);
    if (rv == EXR_ERR_SUCCESS)
      rv = chunks(ctx, &c);
    exr_result_t fin = exr_finish(&ctx);
    if (rv == EXR_ERR_SUCCESS)
      rv = fin;
  }
  if (rv == EXR_ERR_SUCCESS)
    return 0;
  snprintf(err, cap, "%s: OpenEXR: %s", path, e.msg[0] ? e.msg : exr_get_default_error_message(rv));
  return -1;
}
