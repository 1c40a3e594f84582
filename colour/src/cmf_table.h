/* cmf_table.h -- the CIE 1931 2-degree colour-matching functions as colour/CMakeLists.txt
 * generates them from colord-data: x-bar, y-bar, z-bar at bands equally spaced from
 * cs__cmf_start to cs__cmf_end nm (5 nm apart in CIE 015's table). Internal to colour/. */
#ifndef COLOUR_CMF_TABLE_H
#define COLOUR_CMF_TABLE_H

extern const double cs__cmf_start, cs__cmf_end;
extern const int cs__cmf_bands;
extern const double cs__cmf_x[], cs__cmf_y[], cs__cmf_z[];

#endif
