// The star grid's cells (see star_cells.hpp).
#include "backends/vulkan/star_cells.hpp"

#include <cstdint>
#include <functional>
#include <future>

#include "grid/quantile_tails.hpp"
#include "input/parallel.hpp"

namespace expanse::detail::vk {
namespace {

// Uniform cells for the sites: how many per side, and how many sites a cell holds as the typical
// site sees it (`per_bucket` where the density varies little; far more where the cap on cells
// leaves a dense cluster's sites crowded into few cells).
struct UniformPlan {
  int cells = 1;
  double occupancy = 0.0;
};

// Cells per side of the star grid. A search costs the rows and the sites of the boxes it scans
// (empty cells are free: a row of a box is one range of sites), so the cells are sized for the
// density where the typical site lies — the site-weighted median of a coarse histogram — not
// the mean: `per_bucket` sites per cell there. For uniform inputs both agree; for a gaussian
// the median site sees about 8 times the mean density. Capped at 16 cells per site and by the
// largest storage buffer.
//
// Above 2^20 sites the histogram counts every (n / 2^20)-th site (Morton order, so the sample is
// spread over the plane) into the same bins: reading all 16.8M sites was the `vulkan: grid`
// stage's 15-17 ms at 4096^2 on the H100's host. Counted on the 2-core VM, the cells per side
// then stay within 1.1% of the full count's for uniform, gaussian, kuzmin, grid, clusters and
// disk inputs at 2M and 16.8M sites (fewer bins, as many sites to each, lost the small
// clusters: 7,097 cells per side became 4,016).
UniformPlan uniform_cells(const SiteSample& sample, std::size_t n, const Box& bounds, double per_bucket,
                          VkDeviceSize max_buffer) {
  const std::size_t samples = sample.count;
  const double wx = bounds.max_x - bounds.min_x;
  const double wy = bounds.max_y - bounds.min_y;
  const int h = int(std::clamp(std::sqrt(double(n) / 64.0), 1.0, 256.0));
  const std::size_t bin_count = std::size_t(h) * std::size_t(h);
  const double ix = wx > 0 ? h / wx : 0.0, iy = wy > 0 ? h / wy : 0.0;
  // The histogram on all host threads, one set of bins per chunk (at most 256 KB each), summed:
  // done on one thread it was the `vulkan: grid` stage's 121 ms at 4096^2 on the H100's host.
  const std::size_t chunks = detail::chunk_count(samples);
  std::vector<std::vector<std::uint32_t>> chunk_bins(chunks);
  detail::parallel_chunks(samples, chunks, [&](std::size_t c, std::size_t begin, std::size_t end) {
    std::vector<std::uint32_t>& own = chunk_bins[c];
    own.assign(bin_count, 0);
    for (std::size_t i = begin; i < end; ++i) {
      const Point2& p = sample[i];
      ++own[std::size_t(cell_coord(p.y, bounds.min_y, iy, h)) * std::size_t(h) +
            std::size_t(cell_coord(p.x, bounds.min_x, ix, h))];
    }
  });
  std::vector<std::uint32_t> bins = std::move(chunk_bins[0]);
  for (std::size_t c = 1; c < chunks; ++c)
    for (std::size_t b = 0; b < bin_count; ++b) bins[b] += chunk_bins[c][b];
  std::sort(bins.begin(), bins.end(), std::greater<>());
  std::size_t seen = 0;
  double median_bin = 1.0;
  for (std::uint32_t c : bins) {
    seen += c;
    median_bin = c;
    if (2 * seen >= samples) break;
  }
  const double crowding =
      std::clamp(median_bin * double(bins.size()) / double(std::max<std::size_t>(samples, 1)), 1.0, 64.0);
  const double most = std::min({8192.0, std::sqrt(16.0 * double(n) + 1.0),
                                std::floor(std::sqrt(double(max_buffer / 4) - 1.0))});
  UniformPlan plan;
  plan.cells = int(std::clamp(std::ceil(std::sqrt(crowding * double(n) / per_bucket)), 1.0, std::max(1.0, most)));
  // The cells' sites as the typical site sees them: bin b's sites find count_b * n * bins /
  // (samples * cells^2) sites in a cell, weighted by count_b / samples.
  double weighted = 0.0;
  for (std::uint32_t c : bins) weighted += double(c) * double(c);
  plan.occupancy = weighted * double(n) * double(bins.size()) /
                   (double(samples) * double(samples) * double(plan.cells) * double(plan.cells));
  return plan;
}

// Ascending boundaries along one axis: boundary j (1 .. cells - 1) is the (j / cells)-quantile
// of the sample's coordinates, heavy tails weighed (grid/quantile_tails.hpp; kuzmin 10^6 on
// lavapipe: its seam share 0.57% -> 0.19%, medians of five runs 1,931 -> 1,862 ms, against
// plain quantiles).
void quantile_bounds(const SiteSample& sample, std::size_t stride, std::size_t samples, int cells, bool y,
                     double* out) {
  std::vector<double> v(samples);
  for (std::size_t k = 0; k < samples; ++k) v[k] = y ? sample[k * stride].y : sample[k * stride].x;
  std::sort(v.begin(), v.end());
  const int count = int(samples);
  const QuantileTails tails = quantile_tails(v.data(), count, TailWeighing{});
  for (int j = 1; j < cells; ++j) out[j - 1] = quantile_boundary(v.data(), count, cells, j, tails);
}

}  // namespace

StarCells plan_star_cells(const SiteSample& sample, std::size_t n, const Box& bounds, double per_bucket,
                          VkDeviceSize max_buffer, Tuning::Cells cells) {
  StarCells g;
  // Quantile cells where uniform ones would crowd the typical site's cells: kuzmin inputs, whose
  // dense centre is far finer than the coarse histogram (1M sites on lavapipe: 976 sites to the
  // typical cell; 98.9-100% of the triangles were left to the seam stage, 15.4 s, against 2.8 s
  // with quantile cells). Elsewhere uniform cells are cheaper to look up and to walk: gaussian
  // 1M on lavapipe, star shader 0.99 s against 2.26 s with quantile cells (2026-11-25).
  const UniformPlan uniform = uniform_cells(sample, n, bounds, per_bucket, max_buffer);
  g.quantile = cells == Tuning::Cells::automatic ? uniform.occupancy > 4.0 * per_bucket
                                                  : cells == Tuning::Cells::quantile;
  if (g.quantile) {
    // Every row and column holds about 1/cells of the sites, so a cell holds per_bucket of them
    // on average (more near a cluster's centre, where a row and a column of it meet).
    const double most = std::min({8192.0, std::sqrt(16.0 * double(n) + 1.0),
                                  std::floor(std::sqrt(double(max_buffer / 4) - 1.0))});
    g.cells = int(std::clamp(std::ceil(std::sqrt(double(n) / per_bucket)), 1.0, std::max(1.0, most)));
    // 2^17 of the sample (strided): about 45 to a boundary at 4096^2; the two axes sorted on
    // two threads.
    const std::size_t stride = std::max<std::size_t>(1, sample.count >> 17), samples = sample.count / stride;
    g.bounds.resize(2 * std::size_t(g.cells - 1));
    auto along_y = std::async(std::launch::async, [&] {
      quantile_bounds(sample, stride, samples, g.cells, true, g.bounds.data() + (g.cells - 1));
    });
    quantile_bounds(sample, stride, samples, g.cells, false, g.bounds.data());
    along_y.get();
  } else {
    g.cells = uniform.cells;
  }
  g.origin[0] = bounds.min_x;
  g.origin[1] = bounds.min_y;
  const double wx = bounds.max_x - bounds.min_x, wy = bounds.max_y - bounds.min_y;
  g.inv_width[0] = wx > 0 ? double(g.cells) / wx : 0.0;
  g.inv_width[1] = wy > 0 ? double(g.cells) / wy : 0.0;
  return g;
}

}  // namespace expanse::detail::vk
