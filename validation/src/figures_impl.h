/* figures_impl.h -- private to validation/: the results of the figure drivers, the work items
 * they are split into, and the shard files through which a run split over machines is merged
 * (shards.c). A run is a list of independent work items; `--shard K/N` runs item j when
 * j mod N = K - 1 and records the results in DIR/shards/, and `--merge` fills the results of
 * one run from all N shard files and writes the outputs a single run writes. */
#ifndef VALIDATION_FIGURES_IMPL_H
#define VALIDATION_FIGURES_IMPL_H

#include <jansson.h>

#include "validation/figures.h"

/** One row of the rho sweep. */
typedef struct {
  double rho;  /**< tolerance ratio */
  int variant; /**< 0 corrected bounds, 1 printed bounds, 2 certified */
  val_timing_t t;
  val_errors_t e;
} val_sweep_row_t;

/** Everything a figures or sweep run measures. */
typedef struct {
  val_timing_t fig9[VAL_MAX_SPP]; /**< Fig. 9: one per o->spp[] */
  val_errors_t fig10;             /**< Figs. 8 and 10: the measured render at fig8_spp */
  val_errors_t t49, c49;          /**< the targets at target_spp, default and certified */
  val_timing_t tc49;              /**< certified timing at target_spp */
  val_timing_t floor, cfloor;     /**< target_spp with no accuracy asked, default and certified */
  val_sweep_row_t sweep[3 * VAL_MAX_RHO]; /**< the sweep, rho-major, variants in order */
  int nsweep;                             /**< rows of sweep[] */
  int fig8_spp, target_spp;               /**< 9, and 49 when listed (else the largest) */
} val_results_t;

/** The kinds of work item. */
typedef enum {
  VAL_ITEM_FIG9 = 0,    /**< Fig. 9 timing at o->spp[index] */
  VAL_ITEM_FIG8,        /**< Figs. 8 and 10: measured render, images, error map */
  VAL_ITEM_TARGET,      /**< default mode measured at the target spp */
  VAL_ITEM_TARGET_CERT, /**< certified mode measured at the target spp */
  VAL_ITEM_TIME_CERT,   /**< certified mode timed at the target spp */
  VAL_ITEM_NOACC,       /**< no accuracy asked, timed */
  VAL_ITEM_NOACC_CERT,  /**< no accuracy asked, certified, timed */
  VAL_ITEM_SWEEP        /**< sweep row `index` (rho index * 3 + variant) */
} val_item_kind_t;

typedef struct {
  val_item_kind_t kind;
  int index;
} val_item_t;

/** The most work items of a run. */
#define VAL_MAX_ITEMS (VAL_MAX_SPP + 6 + 3 * VAL_MAX_RHO)

/** The figures a run makes: VAL_ONLY_* bits (`pencil sweep`: the sweep; else o->only, or every
 *  figure, the sweep unless o->sweep is 0). */
unsigned val__selected(const val_figures_opts_t *o, int sweep_only);
/** The work items of `pencil figures` (sweep_only 0) or `pencil sweep` (1), in run order. */
int val__items(const val_figures_opts_t *o, int sweep_only, val_item_t *items);
/** The item's stable name in shard files: "fig9:49", "fig8", "sweep:3", ... */
void val__item_name(val_item_t it, const val_figures_opts_t *o, char *buf, size_t cap);
/** Fill fig8_spp, target_spp and nsweep of r from the options (the same in every shard). */
void val__results_init(const val_figures_opts_t *o, val_results_t *r);

/** The run's configuration as recorded in each shard file: what must agree for a merge. */
json_t *val__config_json(const val_figures_opts_t *o, const char *command, int width, int height);

/** Write DIR/shards/COMMAND-K-of-N.json with the results of the items this shard ran. */
int val__shard_write(const val_figures_opts_t *o, const char *command, json_t *config,
                     const val_item_t *items, int nitems, const val_results_t *r);

/** Read every DIR/shards/COMMAND-K-of-N.json, check that they are N shards of one run (same
 *  configuration, every item exactly once), and fill *o (from the configuration; out_dir, log and
 *  plot are kept), *width, *height and *r. *keep holds the parsed configuration, whose strings
 *  o->scene points into: json_decref() it when done. 0, or -1 with the reason on stderr. */
int val__shard_merge(val_figures_opts_t *o, const char *command, int *width, int *height,
                     val_results_t *r, json_t **keep);

#endif
