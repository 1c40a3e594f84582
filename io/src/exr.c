/* exr.c -- the project's one OpenEXR writer, through OpenEXRCore's C API: one scanline part,
 * the image's channels and a renderer's extra ones as 32-bit float, ZIP compression, string
 * attributes and the provenance; and readers of single channels and attributes, so that files
 * can be checked independently of the renderer (1987 paper, section 5, Fig. 10: accuracy
 * recomputed from the checkerboard coordinates of each pixel's centre ray). */
#include <openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image_io_impl.h"
#include "io/image_io.h"
#include "io/output.h"

typedef struct {
  char msg[256]; /* last message of the library's error handler */
} exr_err_t;

/* The error record of the context in use on this thread. The handler cannot ask the context for
 * its user data: exr_get_user_data() takes the context's lock, which the library holds while it
 * writes the header, so a write error there (a full disk) waited for itself. Each context here is
 * started and finished within one function, so that one record a thread is enough. */
static _Thread_local exr_err_t *current_err;

static void on_error(exr_const_context_t ctx, exr_result_t code, const char *msg) {
  (void)ctx;
  if (current_err)
    snprintf(current_err->msg, sizeof current_err->msg, "%s (%s)", msg ? msg : "error",
             exr_get_error_code_as_string(code));
}

static exr_context_initializer_t initializer(exr_err_t *e) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = on_error;
  current_err = e;
  return init;
}

static int fail(char *err, size_t cap, const char *path, const exr_err_t *e, exr_result_t rv) {
  snprintf(err, cap, "%s: OpenEXR: %s", path,
           e->msg[0] ? e->msg : exr_get_default_error_message(rv));
  return -1;
}

/* The channels of one file: the image's and the extra ones. */
typedef struct {
  const rt_image_t *img; /**< NULL: the extra channels only */
  const io_exr_channel_t *extra;
  int nextra;
  int width, height;
} chans_t;

/* Channel called `name`, or NULL. */
static const float *channel_named(const chans_t *c, const char *name) {
  for (int k = 0; k < RT_CH_COUNT && c->img; k++)
    if (strcmp(rt_channel_name((rt_channel_t)k), name) == 0)
      return c->img->ch[k];
  for (int k = 0; k < c->nextra; k++)
    if (strcmp(c->extra[k].name, name) == 0)
      return c->extra[k].data;
  return NULL;
}

/* Define the part: window, compression, channels, attributes and provenance. */
static exr_result_t define_part(exr_context_t ctx, const chans_t *c, const io_attr_t *attrs,
                                int nattrs, exr_compression_t compression) {
  int part;
  const io_provenance_t *p = io_provenance();
  const io_attr_t prov[] = {{"pencil:version", p->version},
                            {"pencil:commit", p->commit},
                            {"pencil:command_line", p->command_line},
                            {"pencil:date", p->date}};
  exr_result_t rv = exr_add_part(ctx, "render", EXR_STORAGE_SCANLINE, &part);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_initialize_required_attr_simple(ctx, part, c->width, c->height, compression);
  for (int k = 0; k < RT_CH_COUNT && c->img && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_add_channel(ctx, part, rt_channel_name((rt_channel_t)k), EXR_PIXEL_FLOAT,
                         EXR_PERCEPTUALLY_LINEAR, 1, 1);
  for (int k = 0; k < c->nextra && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_add_channel(ctx, part, c->extra[k].name, EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1,
                         1);
  for (int k = 0; k < nattrs && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_attr_set_string(ctx, part, attrs[k].key, attrs[k].value);
  for (size_t k = 0; k < sizeof prov / sizeof prov[0] && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_attr_set_string(ctx, part, prov[k].key, prov[k].value);
  return rv;
}

static exr_result_t write_chunks(exr_context_t ctx, const chans_t *c) {
  int32_t lines;
  int width = c->width;
  exr_result_t rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int started = 0;
  for (int y = 0; y < c->height && rv == EXR_ERR_SUCCESS; y += lines) {
    exr_chunk_info_t ci;
    rv = exr_write_scanline_chunk_info(ctx, 0, y, &ci);
    if (rv == EXR_ERR_SUCCESS && started)
      rv = exr_encoding_update(ctx, 0, &ci, &enc);
    else if (rv == EXR_ERR_SUCCESS &&
             (rv = exr_encoding_initialize(ctx, 0, &ci, &enc)) == EXR_ERR_SUCCESS)
      started = 1; /* from here on the pipeline owns buffers: destroy it on every path */
    if (rv != EXR_ERR_SUCCESS)
      break;
    for (int k = 0; k < enc.channel_count; k++) {
      exr_coding_channel_info_t *ch = &enc.channels[k];
      ch->user_bytes_per_element = 4;
      ch->user_data_type = EXR_PIXEL_FLOAT;
      ch->user_pixel_stride = 4;
      ch->user_line_stride = 4 * width;
      ch->encode_from_ptr =
          (const uint8_t *)(channel_named(c, ch->channel_name) + (size_t)y * width);
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

/* Write the file `file` directly (the caller made it a temporary file); errors name `path`. */
static int write_file(const char *file, const char *path, const chans_t c, const io_attr_t *attrs,
                      int nattrs, char *err, size_t cap);

int io_exr_write_file(const char *file, const char *path, const rt_image_t *img,
                      const io_exr_channel_t *extra, int nextra, const io_attr_t *attrs, int nattrs,
                      char *err, size_t cap) {
  return write_file(file, path, (chans_t){img, extra, nextra, img->width, img->height}, attrs,
                    nattrs, err, cap);
}

int io_exr_write_channels_file(const char *file, const char *path, int width, int height,
                               const io_exr_channel_t *ch, int n, const io_attr_t *attrs,
                               int nattrs, char *err, size_t cap) {
  if (width < 1 || height < 1 || n < 1) {
    snprintf(err, cap, "%s: an image needs a size and a channel", path);
    return -1;
  }
  return write_file(file, path, (chans_t){NULL, ch, n, width, height}, attrs, nattrs, err, cap);
}

/* Write `file` once with the given compression. */
static int write_once(const char *file, const char *path, const chans_t *c, const io_attr_t *attrs,
                      int nattrs, exr_compression_t compression, char *err, size_t cap) {
  exr_err_t e = {""};
  exr_context_initializer_t init = initializer(&e);
  exr_context_t ctx = NULL;
  exr_result_t rv = exr_start_write(&ctx, file, EXR_WRITE_FILE_DIRECTLY, &init);
  if (rv != EXR_ERR_SUCCESS)
    return fail(err, cap, path, &e, rv);
  rv = define_part(ctx, c, attrs, nattrs, compression);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_write_header(ctx);
  if (rv == EXR_ERR_SUCCESS)
    rv = write_chunks(ctx, c);
  exr_result_t fin = exr_finish(&ctx);
  if (rv == EXR_ERR_SUCCESS)
    rv = fin;
  return rv == EXR_ERR_SUCCESS ? 0 : fail(err, cap, path, &e, rv);
}

static exr_result_t read_chunks(exr_context_t ctx, const char *const *names, float *const *outs,
                                int n, int width, exr_attr_box2i_t dw, int *found);

/* 0 when every channel of `file` reads back bit for bit as c holds it, 1 when one does not, -1
 * when the file cannot be read. All channels are decoded in one pass over the chunks. */
static int read_back_differs(const char *file, const chans_t *c) {
  exr_err_t e = {""};
  exr_context_initializer_t init = initializer(&e);
  exr_context_t ctx = NULL;
  if (exr_start_read(&ctx, file, &init) != EXR_ERR_SUCCESS)
    return -1;
  size_t plane = (size_t)c->width * (size_t)c->height;
  int nch = (c->img ? RT_CH_COUNT : 0) + c->nextra;
  float *buf = malloc(plane * (size_t)nch * sizeof *buf);
  const char **names = calloc((size_t)nch, sizeof *names);
  float **outs = calloc((size_t)nch, sizeof *outs);
  int *found = calloc((size_t)nch, sizeof *found);
  exr_attr_box2i_t dw;
  exr_result_t rv =
      buf && names && outs && found ? exr_get_data_window(ctx, 0, &dw) : EXR_ERR_OUT_OF_MEMORY;
  for (int k = 0; k < nch && rv == EXR_ERR_SUCCESS; k++) {
    names[k] = c->img && k < RT_CH_COUNT ? rt_channel_name((rt_channel_t)k)
                                         : c->extra[k - (c->img ? RT_CH_COUNT : 0)].name;
    outs[k] = buf + (size_t)k * plane;
  }
  if (rv == EXR_ERR_SUCCESS)
    rv = read_chunks(ctx, names, outs, nch, c->width, dw, found);
  exr_finish(&ctx);
  int result = rv == EXR_ERR_SUCCESS ? 0 : -1;
  for (int k = 0; k < nch && result == 0; k++)
    if (!found[k] || memcmp(outs[k], channel_named(c, names[k]), plane * sizeof *buf) != 0)
      result = 1;
  free(buf);
  free(names);
  free(outs);
  free(found);
  return result;
}

/* Write `file` with ZIP compression and read it back: Debian 12's OpenEXRCore (3.1) stores a
 * chunk whose zlib output is exactly as long as its input as if it were uncompressed, which
 * reads back as garbage (upstream issue 2306, fixed in 3.4). Such a file is written again
 * without compression, and checked again. */
static int write_file(const char *file, const char *path, const chans_t c, const io_attr_t *attrs,
                      int nattrs, char *err, size_t cap) {
  const int nextra = c.nextra;
  const io_exr_channel_t *extra = c.extra;
  for (int k = 0; k < nextra; k++)
    if (!extra[k].data || !extra[k].name || channel_named(&c, extra[k].name) != extra[k].data) {
      snprintf(err, cap, "%s: extra channel %d is missing or duplicates a name", path, k);
      return -1;
    }
  static const exr_compression_t tries[2] = {EXR_COMPRESSION_ZIP, EXR_COMPRESSION_NONE};
  for (int t = 0; t < 2; t++) {
    if (write_once(file, path, &c, attrs, nattrs, tries[t], err, cap) != 0)
      return -1;
    int d = read_back_differs(file, &c);
    if (d == 0)
      return 0;
    if (d < 0) {
      snprintf(err, cap, "%s: OpenEXR: the file just written cannot be read back", path);
      return -1;
    }
  }
  snprintf(err, cap, "%s: OpenEXR: the file just written does not read back as written", path);
  return -1;
}

int io_exr_write(const char *path, const rt_image_t *img, const io_exr_channel_t *extra, int nextra,
                 const io_attr_t *attrs, int nattrs, char *err, size_t cap) {
  io_atomic_t a;
  if (io_atomic_begin(&a, path, err, cap) != 0)
    return -1;
  if (io_exr_write_file(a.tmp, path, img, extra, nextra, attrs, nattrs, err, cap) != 0) {
    io_atomic_abort(&a);
    return -1;
  }
  return io_atomic_commit(&a, err, cap);
}

/* Decode every chunk once, channel names[k] into outs[k] (width x the window's height, row-major)
 * for k < n; found[k] set to 1 for each channel the file has. The other channels are decoded into
 * a scratch chunk and dropped: OpenEXRCore's unpackers for several half channels write through
 * every channel's pointer, and a NULL one (which the generic unpacker skips) crashed them. */
static exr_result_t read_chunks(exr_context_t ctx, const char *const *names, float *const *outs,
                                int n, int width, exr_attr_box2i_t dw, int *found) {
  int32_t lines;
  exr_result_t rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
  if (rv != EXR_ERR_SUCCESS)
    return rv;
  float *scratch = calloc((size_t)width * (size_t)(lines > 0 ? lines : 1), sizeof *scratch);
  if (!scratch)
    return EXR_ERR_OUT_OF_MEMORY;
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
    int any = 0;
    for (int c = 0; c < dec.channel_count; c++) {
      exr_coding_channel_info_t *ch = &dec.channels[c];
      int slot = -1;
      for (int k = 0; k < n && slot < 0; k++)
        if (strcmp(ch->channel_name, names[k]) == 0)
          slot = k;
      if (slot >= 0)
        found[slot] = any = 1;
      ch->user_bytes_per_element = 4;
      ch->user_data_type = EXR_PIXEL_FLOAT;
      ch->user_pixel_stride = 4;
      ch->user_line_stride = 4 * width;
      ch->decode_to_ptr =
          slot >= 0 ? (uint8_t *)(outs[slot] + (size_t)(y - dw.min.y) * width) : (uint8_t *)scratch;
    }
    if (!any)
      break;
    if (first)
      rv = exr_decoding_choose_default_routines(ctx, 0, &dec);
    if (rv == EXR_ERR_SUCCESS)
      rv = exr_decoding_run(ctx, 0, &dec);
  }
  if (started)
    exr_decoding_destroy(ctx, &dec);
  free(scratch);
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
      rv = read_chunks(ctx, &name, &out, 1, *width, dw, &found);
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

int io_exr_read_attr(const char *path, const char *key, char *out, size_t cap_out, char *err,
                     size_t cap) {
  exr_err_t e = {""};
  exr_context_initializer_t init = initializer(&e);
  exr_context_t ctx = NULL;
  exr_result_t rv = exr_start_read(&ctx, path, &init);
  if (rv != EXR_ERR_SUCCESS)
    return fail(err, cap, path, &e, rv);
  int32_t len = 0;
  const char *v = NULL;
  rv = exr_attr_get_string(ctx, 0, key, &len, &v);
  if (rv == EXR_ERR_SUCCESS)
    snprintf(out, cap_out, "%.*s", (int)len, v);
  exr_finish(&ctx);
  if (rv != EXR_ERR_SUCCESS) {
    snprintf(err, cap, "%s: no string attribute '%s'", path, key);
    return -1;
  }
  return 0;
}
