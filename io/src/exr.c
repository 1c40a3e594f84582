/* exr.c -- OpenEXR output through OpenEXRCore's C API: one scanline part, every renderer channel
 * as 32-bit float, ZIP compression; and a reader of single channels so that files can be
 * checked independently of the renderer (paper section 5, Fig. 10: accuracy recomputed from
 * the checkerboard coordinates of each pixel's centre ray). */
#include <openexr.h>
#include <stdio.h>
#include <string.h>

#include "io/image_io.h"

typedef struct {
  char msg[256]; /* last message of the library's error handler */
} exr_err_t;

static void on_error(exr_const_context_t ctx, exr_result_t code, const char *msg) {
  void *ud = NULL;
  if (exr_get_user_data(ctx, &ud) == EXR_ERR_SUCCESS && ud)
    snprintf(((exr_err_t *)ud)->msg, sizeof((exr_err_t *)ud)->msg, "%s (%s)", msg ? msg : "error",
             exr_get_error_code_as_string(code));
}

static exr_context_initializer_t initializer(exr_err_t *e) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = on_error;
  init.user_data = e;
  return init;
}

static int fail(char *err, size_t cap, const char *path, const exr_err_t *e, exr_result_t rv) {
  snprintf(err, cap, "%s: OpenEXR: %s", path,
           e->msg[0] ? e->msg : exr_get_default_error_message(rv));
  return -1;
}

/* Define the part: window, compression, channels, metadata. */
static exr_result_t define_part(exr_context_t ctx, const rt_image_t *img,
                                const char *const (*meta)[2], int nmeta) {
  int part;
  exr_result_t rv = exr_add_part(ctx, "render", EXR_STORAGE_SCANLINE, &part);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_initialize_required_attr_simple(ctx, part, img->width, img->height,
                                             EXR_COMPRESSION_ZIP);
  for (int c = 0; c < RT_CH_COUNT && rv == EXR_ERR_SUCCESS; c++)
    rv = exr_add_channel(ctx, part, rt_channel_name((rt_channel_t)c), EXR_PIXEL_FLOAT,
                         EXR_PERCEPTUALLY_LINEAR, 1, 1);
  for (int k = 0; k < nmeta && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_attr_set_string(ctx, part, meta[k][0], meta[k][1]);
  return rv;
}

/* Channel of img called `name`, or NULL. */
static const float *channel_named(const rt_image_t *img, const char *name) {
  for (int c = 0; c < RT_CH_COUNT; c++)
    if (strcmp(rt_channel_name((rt_channel_t)c), name) == 0)
      return img->ch[c];
  return NULL;
}

static exr_result_t write_chunks(exr_context_t ctx, const rt_image_t *img) {
  int32_t lines;
  exr_result_t rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int started = 0;
  for (int y = 0; y < img->height && rv == EXR_ERR_SUCCESS; y += lines) {
    exr_chunk_info_t ci;
    rv = exr_write_scanline_chunk_info(ctx, 0, y, &ci);
    if (rv == EXR_ERR_SUCCESS && started)
      rv = exr_encoding_update(ctx, 0, &ci, &enc);
    else if (rv == EXR_ERR_SUCCESS &&
             (rv = exr_encoding_initialize(ctx, 0, &ci, &enc)) == EXR_ERR_SUCCESS)
      started = 1; /* from here on the pipeline owns buffers: destroy it on every path */
    if (rv != EXR_ERR_SUCCESS)
      break;
    for (int c = 0; c < enc.channel_count; c++) {
      exr_coding_channel_info_t *ch = &enc.channels[c];
      ch->user_bytes_per_element = 4;
      ch->user_data_type = EXR_PIXEL_FLOAT;
      ch->user_pixel_stride = 4;
      ch->user_line_stride = 4 * img->width;
      ch->encode_from_ptr =
          (const uint8_t *)(channel_named(img, ch->channel_name) + (size_t)y * img->width);
    }
    if (y == 0)
      rv = exr_encoding_choose_default_routines(ctx, 0, &enc);
    if (rv == EXR_ERR_SUCCESS)
      rv = exr_encoding_run(ctx, 0, &enc);
  }
  if (started)
    exr_encoding_destroy(ctx, &enc);
  return rv;
}

int io_exr_write(const char *path, const rt_image_t *img, const char *const (*meta)[2], int nmeta,
                 char *err, size_t cap) {
  exr_err_t e = {""};
  exr_context_initializer_t init = initializer(&e);
  exr_context_t ctx = NULL;
  /* a temporary file renamed on success: a failed write leaves no partial image */
  exr_result_t rv = exr_start_write(&ctx, path, EXR_INTERMEDIATE_TEMP_FILE, &init);
  if (rv != EXR_ERR_SUCCESS)
    return fail(err, cap, path, &e, rv);
  rv = define_part(ctx, img, meta, nmeta);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_write_header(ctx);
  if (rv == EXR_ERR_SUCCESS)
    rv = write_chunks(ctx, img);
  exr_result_t fin = exr_finish(&ctx);
  if (rv == EXR_ERR_SUCCESS)
    rv = fin;
  return rv == EXR_ERR_SUCCESS ? 0 : fail(err, cap, path, &e, rv);
}

static exr_result_t read_chunks(exr_context_t ctx, const char *name, float *out, int width,
                                exr_attr_box2i_t dw, int *found) {
  int32_t lines;
  exr_result_t rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  int started = 0;
  for (int y = dw.min.y; y <= dw.max.y && rv == EXR_ERR_SUCCESS; y += lines) {
    exr_chunk_info_t ci;
    rv = exr_read_scanline_chunk_info(ctx, 0, y, &ci);
    int first = !started;
    if (rv == EXR_ERR_SUCCESS && started)
      rv = exr_decoding_update(ctx, 0, &ci, &dec);
    else if (rv == EXR_ERR_SUCCESS &&
             (rv = exr_decoding_initialize(ctx, 0, &ci, &dec)) == EXR_ERR_SUCCESS)
      started = 1;
    if (rv != EXR_ERR_SUCCESS)
      break;
    for (int c = 0; c < dec.channel_count; c++) {
      exr_coding_channel_info_t *ch = &dec.channels[c];
      int want = strcmp(ch->channel_name, name) == 0;
      *found |= want;
      ch->user_bytes_per_element = 4;
      ch->user_data_type = EXR_PIXEL_FLOAT;
      ch->user_pixel_stride = 4;
      ch->user_line_stride = 4 * width;
      ch->decode_to_ptr = want ? (uint8_t *)(out + (size_t)(y - dw.min.y) * width) : NULL;
    }
    if (!*found)
      break;
    if (first)
      rv = exr_decoding_choose_default_routines(ctx, 0, &dec);
    if (rv == EXR_ERR_SUCCESS)
      rv = exr_decoding_run(ctx, 0, &dec);
  }
  if (started)
    exr_decoding_destroy(ctx, &dec);
  return rv;
}

int io_exr_read_channel(const char *path, const char *name, float *out, int *width, int *height,
                        char *err, size_t cap) {
  exr_err_t e = {""};
  exr_context_initializer_t init = initializer(&e);
  exr_context_t ctx = NULL;
  exr_result_t rv = exr_start_read(&ctx, path, &init);
  if (rv != EXR_ERR_SUCCESS)
    return fail(err, cap, path, &e, rv);
  exr_attr_box2i_t dw;
  int found = 0;
  rv = exr_get_data_window(ctx, 0, &dw);
  if (rv == EXR_ERR_SUCCESS) {
    *width = dw.max.x - dw.min.x + 1;
    *height = dw.max.y - dw.min.y + 1;
    if (out)
      rv = read_chunks(ctx, name, out, *width, dw, &found);
  }
  exr_finish(&ctx);
  if (rv != EXR_ERR_SUCCESS)
    return fail(err, cap, path, &e, rv);
  if (out && !found) {
    snprintf(err, cap, "%s: no channel '%s'", path, name);
    return -1;
  }
  return 0;
}
