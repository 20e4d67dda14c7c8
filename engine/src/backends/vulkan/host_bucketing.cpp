#include "backends/vulkan/host_bucketing.hpp"

#include <algorithm>
#include <atomic>

#include "backends/vulkan/host_threads.hpp"
#include "expanse/error.hpp"

namespace expanse::detail::vk {
namespace {

// Sites sorted by cell for the star kernel, written straight into `points`, `cell_start` and
// `predecessor` (mapped memory: the device's own on unified-memory devices, else staging).
// A counting sort in O(n + cells), its passes split over the host threads; sites keep their
// SiteSet order within a cell, so the result does not depend on the thread count.
StarGrid bucket_stars(const GrowInput& input, const StarCells& plan, Point2* points,
                      std::int32_t* cell_start, std::int32_t* predecessor) {
  const SiteSet& sites = input.sites;
  const std::size_t n = std::size_t(sites.size());
  const int cells = plan.cells;
  StarGrid g;
  const std::size_t cell_count = std::size_t(cells) * std::size_t(cells);
  // Each worker counts into its own array of all cells: at most 2^24 counts in all (64 MB).
  const unsigned workers = unsigned(std::clamp<std::size_t>(
      (std::size_t(1) << 24) / std::max<std::size_t>(cell_count, 1), 1, host_workers(n)));
  std::vector<std::int32_t> cell(n);
  std::vector<std::vector<std::int32_t>> fill(workers);
  parallel_chunks(n, workers, [&](std::size_t begin, std::size_t end, unsigned w) {
    fill[w].assign(cell_count, 0);  // zeroed (first touched) by the thread that counts in it
    std::int32_t* count = fill[w].data();
    for (std::size_t i = begin; i < end; ++i) {
      const Point2& p = sites.points[i];
      cell[i] = plan.y(p.y) * cells + plan.x(p.x);
      ++count[cell[i]];
    }
  });
  // cell_start, and each worker's first slot in each cell: a prefix sum over cells (then
  // workers), in two parallel passes over ranges of cells.
  std::vector<std::int32_t> range_sum(workers + 1, 0);
  parallel_chunks(cell_count, workers, [&](std::size_t begin, std::size_t end, unsigned r) {
    std::int32_t sum = 0;
    for (std::size_t c = begin; c < end; ++c)
      for (unsigned w = 0; w < workers; ++w) sum += fill[w][c];
    range_sum[r + 1] = sum;
  });
  for (unsigned r = 0; r < workers; ++r) range_sum[r + 1] += range_sum[r];
  parallel_chunks(cell_count, workers, [&](std::size_t begin, std::size_t end, unsigned r) {
    std::int32_t running = range_sum[r];
    for (std::size_t c = begin; c < end; ++c) {
      cell_start[c] = running;
      for (unsigned w = 0; w < workers; ++w) {
        const std::int32_t here = fill[w][c];
        fill[w][c] = running;
        running += here;
      }
    }
  });
  cell_start[cell_count] = std::int32_t(n);
  std::vector<std::int32_t> to_sorted(n);
  g.to_site.resize(n);
  parallel_chunks(n, workers, [&](std::size_t begin, std::size_t end, unsigned w) {
    std::int32_t* next = fill[w].data();
    for (std::size_t i = begin; i < end; ++i) {
      const std::int32_t at = next[cell[i]]++;
      to_sorted[i] = at;
      g.to_site[std::size_t(at)] = std::int32_t(i);
      points[at] = sites.points[i];
    }
  });
  parallel_chunks(n, workers, [&](std::size_t begin, std::size_t end, unsigned) {
    for (std::size_t k = begin; k < end; ++k) {
      const std::int32_t p = input.hull.predecessor[std::size_t(g.to_site[k])];
      predecessor[k] = p < 0 ? -1 : to_sorted[std::size_t(p)];
    }
  });
  return g;
}

}  // namespace

void bucket_on_host(Context& ctx, const GrowInput& input, const StarCells& plan, Buffer& sites,
                    Buffer& cell_start, Buffer& predecessor, StarGrid& grid) {
  const std::size_t n = std::size_t(input.sites.size());
  const std::size_t cell_entries = std::size_t(plan.cells) * std::size_t(plan.cells) + 1;
  if (sites.mapped() && cell_start.mapped() && predecessor.mapped()) {
    grid = bucket_stars(input, plan, static_cast<Point2*>(sites.mapped()),
                        static_cast<std::int32_t*>(cell_start.mapped()),
                        static_cast<std::int32_t*>(predecessor.mapped()));
    return;
  }
  std::vector<Point2> points(n);
  std::vector<std::int32_t> starts(cell_entries), predecessors(n);
  grid = bucket_stars(input, plan, points.data(), starts.data(), predecessors.data());
  const StagingRing::Upload pieces[] = {
      {points.data(), sites.handle(), 0, bytes_of(n, 16)},
      {starts.data(), cell_start.handle(), 0, bytes_of(cell_entries, 4)},
      {predecessors.data(), predecessor.handle(), 0, bytes_of(n, 4)}};
  ctx.staging().upload(pieces);
}

void restore_on_host(const StarGrid& g, const std::int32_t* raw, std::size_t count,
                     PartialTriangulation& partial) {
  const std::size_t n = g.to_site.size();
  std::atomic<bool> bad{false};
  parallel_chunks(count, host_workers(count), [&](std::size_t begin, std::size_t end, unsigned) {
    for (std::size_t t = begin; t < end; ++t)
      for (std::size_t k = 0; k < 3; ++k) {
        const std::int32_t id = raw[3 * t + k];
        if (id < 0 || std::size_t(id) >= n) {
          bad = true;
          return;
        }
        partial.triangles[t][k] = g.to_site[std::size_t(id)];
      }
  });
  if (bad) throw Error(ErrorCode::internal, "Vulkan: the device returned an invalid site id");
}

}  // namespace expanse::detail::vk
