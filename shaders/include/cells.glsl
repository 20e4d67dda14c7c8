// The cell index rule shared by every kernel and the host (vulkan_backend.cpp, cell_coord):
// clamp(floor((x - origin) * inv_width), 0, G - 1), two correctly rounded operations, which is
// monotone in x: a site whose coordinate lies in [lo, hi] is in a cell between cell_of(lo) and
// cell_of(hi). So a box test in cell space can never hide a site, whatever the rounding.
#ifndef EXPANSE_CELLS_GLSL
#define EXPANSE_CELLS_GLSL

#extension GL_ARB_gpu_shader_fp64 : enable

// Absolute slack: eight ulps of 1, the largest site magnitude (SiteSet scales below 1).
const double ABS_MARGIN = 1.7763568394002505e-15lf;

int cell_coord(double x, double origin, double inv_width, int cells) {
  precise double t = (x - origin) * inv_width;
  double f = clamp(floor(t), 0.0lf, double(cells - 1));
  return int(f);
}

#endif
