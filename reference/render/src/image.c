/* image.c -- the float image with RGB and the auxiliary accuracy channels (paper section 5,
 * Fig. 10: errors are distances between checkerboard points of the two tracers). */
#include <math.h>
#include <stdlib.h>

#include "render/render.h"

static const char *const channel_names[RT_CH_COUNT] = {
    "R", "G", "B", "Z", "id", "pathT.u", "pathT.v", "pathT.k", "pathR.u", "pathR.v", "pathR.k"};

const char *rt_channel_name(rt_channel_t c) {
  return (unsigned)c < RT_CH_COUNT ? channel_names[c] : "?";
}

rt_status_t rt_image_alloc(rt_image_t *img, int width, int height) {
  img->width = img->height = 0;
  for (int c = 0; c < RT_CH_COUNT; c++)
    img->ch[c] = NULL;
  if (width < 1 || height < 1 || (size_t)width > ((size_t)1 << 30) / (size_t)height)
    return RT_EINVAL;
  size_t n = (size_t)width * (size_t)height;
  for (int c = 0; c < RT_CH_COUNT; c++)
    if (!(img->ch[c] = calloc(n, sizeof(float)))) {
      rt_image_free(img);
      return RT_ENOMEM;
    }
  img->width = width;
  img->height = height;
  return RT_OK;
}

void rt_image_free(rt_image_t *img) {
  for (int c = 0; c < RT_CH_COUNT; c++) {
    free(img->ch[c]);
    img->ch[c] = NULL;
  }
  img->width = img->height = 0;
}
