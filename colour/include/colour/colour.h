/* colour.h -- colour science for spectral rendering (issue 22): the CIE 1931 2-degree standard
 * observer, linear sRGB, CIELAB and the CIEDE2000 colour difference, and the RGB weights of
 * wavelength bins by which a spectral renderer turns radiance per wavelength into an RGB image.
 *
 * Sources (full references in docs/spectral.md):
 * - the observer: CIE 015:2004, Colorimetry, table T.4 (x-bar, y-bar, z-bar, 360-830 nm at 5 nm),
 *   read at build time from Debian's colord-data; between table rows the functions are linear;
 * - linear sRGB: IEC 61966-2-1:1999, its primaries' and D65 white's chromaticities; the matrices
 *   are derived from them here (cs_srgb_from_xyz), not copied;
 * - CIELAB: CIE 015:2004 section 8.2.1;
 * - CIEDE2000: CIE 142-2001, as Sharma, Wu and Dalal (2005) spell out its implementation.
 *
 * Wavelengths are in nm. Prefix cs_. Pure math: no I/O, no allocation. */
#ifndef COLOUR_COLOUR_H
#define COLOUR_COLOUR_H

/** The visible range spectral rendering samples, nm (docs/spectral.md). */
#define CS_LAMBDA_LO 380.0
#define CS_LAMBDA_HI 780.0

/** The observer's table's range, nm (360 and 830 for CIE 015's). */
void cs_cmf_range(double *lo_nm, double *hi_nm);

/** x-bar, y-bar, z-bar at lambda (linear between the table's rows); 0 outside its range. */
void cs_cmf(double lambda_nm, double xyz[3]);

/** The integral of x-bar, y-bar, z-bar over [a, b] nm (a <= b; the parts outside the table count
 *  0), exact for the piecewise-linear functions of cs_cmf(). */
void cs_cmf_integral(double a_nm, double b_nm, double xyz[3]);

/** M with linear sRGB = M XYZ (D65 white at Y = 1 maps to (1, 1, 1)), derived from the primaries
 *  R (0.64, 0.33), G (0.30, 0.60), B (0.15, 0.06) and the white (0.3127, 0.3290). */
void cs_srgb_from_xyz(double m[3][3]);
/** Its inverse: XYZ = M^-1 linear sRGB. */
void cs_xyz_from_srgb(double m[3][3]);

/** XYZ of the D65 white at Y = 1 (the sRGB white). */
void cs_white_d65(double xyz[3]);

/** CIELAB of xyz relative to the white `white` (Y of the white is L* = 100). */
void cs_lab_from_xyz(const double xyz[3], const double white[3], double lab[3]);

/** CIELAB of a linear sRGB colour, relative to the sRGB white (1, 1, 1). */
void cs_lab_from_srgb(const double rgb[3], double lab[3]);

/** The CIEDE2000 difference of two CIELAB colours, kL = kC = kH = 1. */
double cs_delta_e2000(const double lab1[3], const double lab2[3]);

/** n equal bins over [lo, hi] nm (n >= 1, lo < hi, inside the table): centre[i] and the RGB
 *  weight w[i]: w_c(i) = the integral over bin i of c-bar / its integral over [lo, hi], c-bar the
 *  linear-sRGB colour-matching function (r-bar, g-bar, b-bar) = M (x-bar, y-bar, z-bar). Each
 *  channel's weights sum to 1, so light of equal energy at every wavelength comes out (1, 1, 1):
 *  a spectral render of a scene that does not disperse equals its RGB render. Weights may be
 *  negative (r-bar's lobe below 546 nm). 0, or -1 for bad arguments. */
int cs_bins(int n, double lo_nm, double hi_nm, double *centre, double (*w)[3]);

#endif
