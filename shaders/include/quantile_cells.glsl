// Quantile cells (the star grid on clustered or heavy-tailed inputs): along each axis the cell
// boundaries are quantiles of a sample of the sites' coordinates, so every row and every column
// of cells holds about the same share of the sites. A coordinate's cell is the number of
// boundaries at or below it: monotone in the coordinate (the box tests' only need, as for
// cells.glsl's uniform cells), and made of comparisons alone, so the host (star_cells.cpp) and
// every device agree exactly.
//
// The including shader declares `double cell_bounds[]`: cells - 1 boundaries for x from index 0,
// then cells - 1 for y, each ascending.
#ifndef EXPANSE_QUANTILE_CELLS_GLSL
#define EXPANSE_QUANTILE_CELLS_GLSL

#extension GL_ARB_gpu_shader_fp64 : enable

// The count of boundaries cell_bounds[base .. base + count) at or below v: a binary search.
int quantile_cell(double v, int base, int count) {
  int lo = 0, hi = count;
  while (lo < hi) {
    const int mid = (lo + hi) >> 1;
    if (cell_bounds[base + mid] <= v)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

#endif
