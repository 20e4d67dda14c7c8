#pragma once
// The CUDA backend's per-site layout run on the CPU: the same grid (star_grid.hpp) and the same
// star walk (star_walk.cuh), one site after another. Used by tests and by the work count
// (bench/src/star_work.cpp) on machines without a GPU; the backend itself never calls it.
#if defined(__CUDACC__)
#error "star_host.hpp is host code: include it from C++ translation units only"
#endif
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <numeric>
#include <thread>
#include <vector>

#include "expanse/types.hpp"
#include "hull/convex_hull.hpp"
#include "input/site_set.hpp"
#include "star_grid.hpp"
#include "star_scan.cuh"
#include "star_view.cuh"

namespace expanse::detail::cuda {

/// What the star kernel's counters say, summed over every site.
struct StarWorkTotals {
  std::uint64_t sites = 0;
  std::uint64_t deferred = 0;
  std::uint64_t predicates = 0;
  std::uint64_t work = 0;            ///< cells + sites visited, all sites
  std::uint64_t max_work = 0;        ///< the most one site spent
  std::uint64_t sites_over_4096 = 0;
  std::uint64_t sites_over_budget = 0;
  /// Sites whose work exceeds 2^11, 2^12, ... 2^16 units: what a smaller budget would defer.
  std::array<std::uint64_t, 6> sites_over_pow2{};
  std::uint64_t deferred_undecided = 0;  ///< by reason (DeferReason); budget overruns count here
  std::uint64_t deferred_full_row = 0;
  std::uint64_t deferred_no_apex = 0;
  /// Lock-step cost: over consecutive groups of 8 (lavapipe's SIMD batch) or 32 (a warp) sites
  /// in walk order, the sum of each group's most work. work / (group size * this) is the share
  /// of the lanes' time spent on their own site's work when a group runs until its slowest
  /// lane is done.
  std::uint64_t lockstep_work_8 = 0;
  std::uint64_t lockstep_work_32 = 0;
  /// Two phases: the odd sites whose stars their inboxes held whole (walk_from_inbox), and of
  /// those, with verify_inbox_walks, the ones whose full walk made another star (must be 0).
  std::uint64_t from_inbox = 0;
  std::uint64_t inbox_walk_mismatches = 0;
};

class HostStarLayout {
 public:
  /// Buckets the sites exactly as grow_per_site does (quantile boundaries from the same hashed
  /// sample, stable sort by cell), ready to walk. `tuning`: the knobs that shape the grid (tails,
  /// tail_columns).
  HostStarLayout(const SiteSet& sites, const Hull& hull, double sites_per_bucket, bool quantile,
                 const Tuning& tuning = {}) {
    const std::size_t n = sites.points.size();
    const GridShape finest = make_grid_shape(sites.bounds, n, sites_per_bucket);
    const GridShape shape = !quantile ? uniform_cells_shape(sites.bounds, n, sites_per_bucket, sites.integer_coordinates)
                                      : quantile_shape(finest, sites.bounds);
    grid_ = make_grid_view(shape, sites.bounds);
    exact_lattice_ = exact_lattice_arithmetic(sites);
    apply_first_box(grid_, !quantile, sites);
    bool heavy_x_tails = false;
    if (quantile) {
      const int samples = quantile_sample_count(n);
      std::vector<double> xs(samples), ys(samples);
      for (int i = 0; i < samples; ++i) {
        const Point2 p = sites.points[quantile_sample_site(i, static_cast<int>(n), samples)];
        xs[i] = p.x;
        ys[i] = p.y;
      }
      std::sort(xs.begin(), xs.end());
      std::sort(ys.begin(), ys.end());
      xb_.assign(shape.gx + 1, 0.0);
      yb_.assign(shape.gy + 1, 0.0);
      const TailWeighing weighing = tuning.tails;
      const QuantileTails x_tails = quantile_tails(xs.data(), samples, weighing);
      const QuantileTails y_tails = quantile_tails(ys.data(), samples, weighing);
      heavy_x_tails = x_tails.tail > 0;
      for (int j = 1; j < shape.gx; ++j) xb_[j] = quantile_boundary(xs.data(), samples, shape.gx, j, x_tails);
      for (int j = 1; j < shape.gy; ++j) yb_[j] = quantile_boundary(ys.data(), samples, shape.gy, j, y_tails);
      grid_.xb = xb_.data();
      grid_.yb = yb_.data();
      fill_guide(xb_, shape.gx, grid_.min_x, grid_.max_x, x_guide_, grid_.x_guide);
      fill_guide(yb_, shape.gy, grid_.min_y, grid_.max_y, y_guide_, grid_.y_guide);
    }
    std::vector<std::uint32_t> keys(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Point2 p = sites.points[i];
      keys[i] = static_cast<std::uint32_t>(grid_.cell_y(p.y) * grid_.gx + grid_.cell_x(p.x));
    }
    to_site_.resize(n);
    std::iota(to_site_.begin(), to_site_.end(), 0);
    std::stable_sort(to_site_.begin(), to_site_.end(), [&](int a, int b) { return keys[a] < keys[b]; });
    std::vector<int> rank(n);
    points_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      rank[to_site_[i]] = static_cast<int>(i);
      points_[i] = make_double2(sites.points[to_site_[i]].x, sites.points[to_site_[i]].y);
    }
    const std::size_t cells = static_cast<std::size_t>(shape.gx) * shape.gy;
    cell_start_.assign(cells + 1, 0);
    for (std::uint32_t key : keys) ++cell_start_[key + 1];
    std::partial_sum(cell_start_.begin(), cell_start_.end(), cell_start_.begin());
    pred_.assign(n, -1);
    const std::size_t h = hull.sites.size();
    for (std::size_t t = 0; t < h; ++t) pred_[rank[hull.sites[t]]] = rank[hull.sites[t == 0 ? h - 1 : t - 1]];
    grid_.points = points_.data();
    grid_.cell_start = cell_start_.data();
    if (quantile && tail_columns_wanted(heavy_x_tails, tuning.tail_columns)) use_tail_columns(true);
  }

  /// With `on`, the walks scan tall boxes in the grid's outer columns a column at a time
  /// (TailColumns), copied here as build_tail_columns (star_kernels.cu) copies them: the outer
  /// columns' cells column after column, each cell's sites in the grid's order. On by default
  /// where the kernels take them: quantile cells whose x-tails are heavy (any quantile cells with
  /// Tuning::tail_columns forced on).
  void use_tail_columns(bool on) {
    grid_.tail = {};
    const int width = tail_columns_width(grid_.gx), gx = grid_.gx, gy = grid_.gy;
    if (!on || !grid_.xb || width == 0) return;
    tail_start_.assign(static_cast<std::size_t>(2 * width) * gy + 1, 0);
    tail_ids_.clear();
    for (int j = 0; j < 2 * width; ++j) {
      const int x = tail_column_of_grid(j, gx, width);
      for (int r = 0; r < gy; ++r) {
        tail_start_[static_cast<std::size_t>(j) * gy + r] = static_cast<std::uint32_t>(tail_ids_.size());
        const std::size_t c = static_cast<std::size_t>(r) * gx + x;
        for (std::uint32_t q = cell_start_[c]; q < cell_start_[c + 1]; ++q) tail_ids_.push_back(static_cast<int>(q));
      }
    }
    tail_start_.back() = static_cast<std::uint32_t>(tail_ids_.size());
    grid_.tail = {tail_start_.data(), tail_ids_.data(), width};
  }

  /// With `on`, the walks scan the grid's boundary strips where they are the shorter scan (the
  /// kernels' edge walks and second pass: walk_star_boxes' Strips), built here as
  /// boundary_strips_kernel builds them: each side's sites in cell order, stably sorted by key.
  void use_strips(bool on) {
    strips_ = on;
    if (!on || !strip_ids_.empty() || !strips_fit(grid_.gx, grid_.gy)) return;
    const int capacity = strip_capacity(grid_.gx, grid_.gy);
    strip_keys_.assign(4 * static_cast<std::size_t>(capacity), 0xffffffffu);
    strip_ids_.assign(strip_keys_.size(), -1);
    for (int s = 0; s < 4; ++s) {
      std::vector<std::pair<std::uint32_t, int>> side;
      for (int j = 0; j < strip_cells(s, grid_.gx, grid_.gy); ++j) {
        const int c = strip_cell(s, j, grid_.gx, grid_.gy);
        for (std::uint32_t q = cell_start_[c]; q < cell_start_[c + 1]; ++q)
          side.emplace_back(strip_key(strip_coordinate(s, points_[q])), static_cast<int>(q));
      }
      std::stable_sort(side.begin(), side.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      strip_length_[s] = side.size() <= static_cast<std::size_t>(capacity) ? static_cast<int>(side.size()) : 0;
      for (int k = 0; k < strip_length_[s]; ++k) {
        strip_keys_[static_cast<std::size_t>(s) * capacity + k] = side[k].first;
        strip_ids_[static_cast<std::size_t>(s) * capacity + k] = side[k].second;
      }
    }
    grid_.strips = {strip_keys_.data(), strip_ids_.data(), strip_length_.data(), capacity};
  }

  /// Walks every star as the kernel's threads would (budget as Tuning::budget; 0: the
  /// kernel's default for the search), spread over
  /// `threads` host threads; the result does not depend on their number.
  /// With `two_phases` (boxes only), the even sites are walked first and post their triangles
  /// to the odd ones, whose walks then read them (StarInbox), as the kernels' phases do.
  StarWorkTotals walk_all(unsigned budget = 0, unsigned threads = 1, StarSearch search = StarSearch::boxes,
                          bool two_phases = false) {
    if (budget == 0) budget = default_budget(search);
    const std::size_t n = points_.size();
    star_.assign(n * kStar, -1);
    info_.assign(n, 0);
    threads = std::max(1u, threads);
    std::vector<StarWorkTotals> part(threads);
    work_of_.assign(n, 0);
    const int phases = two_phases && search == StarSearch::boxes ? 2 : 1;
    std::vector<int> inbox_slots(phases == 2 ? (n / 2 + 1) * kInboxWords : 0, -1);
    std::vector<std::uint32_t> inbox_counts(phases == 2 ? n / 2 + 1 : 0, 0);
    StarInbox inbox{phases == 2 ? inbox_slots.data() : nullptr, inbox_counts.data(), false};
    int phase = 0;
    auto walk_range = [&](unsigned p) {
      StarWorkTotals& totals = part[p];
      for (std::size_t i = n * p / threads; i < n * (p + 1) / threads; ++i) {
        if (static_cast<int>(i % phases) != phase) continue;
        int* row = star_.data() + i * kStar;
        const int s = static_cast<int>(i);
        StarWalk w;
        auto reading_walk = [&](int* into) {
          return exact_lattice_
                     ? walk_star_by<StarSearch::boxes, true, false, true>(grid_, pred_.data(), s, into, budget, inbox)
                     : walk_star_by<StarSearch::boxes, false, false, true>(grid_, pred_.data(), s, into, budget, inbox);
        };
        if (search == StarSearch::rings) {
          w = walk_star_by<StarSearch::rings>(grid_, pred_.data(), s, row, budget);
        } else if (int owned = 0; inbox.reading && walk_from_inbox(pred_.data(), s, nullptr, inbox, &w, &owned)) {
          // As the second phase's inbox_star_kernel: no search, the row written by a second
          // walk. With verify_inbox_walks, the full walk must make the same star.
          walk_from_inbox(pred_.data(), s, row, inbox, &w, &owned);
          ++totals.from_inbox;
          if (verify_inbox_walks_) {
            std::array<int, kStar> full{};
            full.fill(-1);
            const StarWalk f = reading_walk(full.data());
            const std::uint32_t info = star_info(w);
            bool same = f.ok && star_info(f) == info;
            for (int t = 0; same && t < star_degree(info); ++t) same = star_at(full.data(), info, 0, t) == star_at(row, info, 0, t);
            same = same && owned == owned_triangles(star_.data(), info, s);
            totals.inbox_walk_mismatches += !same;
          }
        } else if (inbox.reading)
          w = reading_walk(row);
        else
          w = walk_site(s, row, budget, false);
        ++totals.sites;
        work_of_[i] = w.work;
        totals.predicates += w.predicates;
        totals.work += w.work;
        totals.max_work = std::max<std::uint64_t>(totals.max_work, w.work);
        totals.sites_over_4096 += w.work > 4096;
        totals.sites_over_budget += w.work > budget;
        for (std::size_t k = 0; k < totals.sites_over_pow2.size(); ++k)
          totals.sites_over_pow2[k] += w.work > (1u << (11 + k));
        if (!w.ok) {
          info_[i] = kDeferredBit;
          ++totals.deferred;
          totals.deferred_undecided += w.reason == DeferReason::undecided;
          totals.deferred_full_row += w.reason == DeferReason::full_row;
          totals.deferred_no_apex += w.reason == DeferReason::no_apex;
          continue;
        }
        info_[i] = star_info(w);
      }
    };
    for (; phase < phases; ++phase) {
      std::vector<std::thread> workers;
      for (unsigned p = 1; p < threads; ++p) workers.emplace_back(walk_range, p);
      walk_range(0);
      for (auto& worker : workers) worker.join();
      if (inbox.posting()) {
        for (std::size_t u = 0; u < n; u += 2)
          if (!star_deferred(info_[u]))
            post_star(inbox, star_.data(), info_[u], static_cast<int>(u), [](std::uint32_t* c) { return (*c)++; });
        inbox.reading = true;
      }
    }
    StarWorkTotals totals;
    for (const StarWorkTotals& t : part) {
      totals.sites += t.sites;
      totals.deferred += t.deferred;
      totals.predicates += t.predicates;
      totals.work += t.work;
      totals.max_work = std::max(totals.max_work, t.max_work);
      totals.sites_over_4096 += t.sites_over_4096;
      totals.sites_over_budget += t.sites_over_budget;
      for (std::size_t k = 0; k < totals.sites_over_pow2.size(); ++k) totals.sites_over_pow2[k] += t.sites_over_pow2[k];
      totals.deferred_undecided += t.deferred_undecided;
      totals.deferred_full_row += t.deferred_full_row;
      totals.deferred_no_apex += t.deferred_no_apex;
      totals.from_inbox += t.from_inbox;
      totals.inbox_walk_mismatches += t.inbox_walk_mismatches;
    }
    // Groups of a phase's sites, as its kernel's threads take them.
    auto lockstep = [&](std::size_t group) {
      std::uint64_t sum = 0;
      const std::size_t stride = static_cast<std::size_t>(phases);
      for (std::size_t phase = 0; phase < stride; ++phase)
        for (std::size_t first = phase; first < n; first += group * stride) {
          std::uint32_t most = 0;
          for (std::size_t i = first; i < std::min(n, first + group * stride); i += stride) most = std::max(most, work_of_[i]);
          sum += most;
        }
      return sum;
    };
    totals.lockstep_work_8 = lockstep(8);
    totals.lockstep_work_32 = lockstep(32);
    return totals;
  }

  /// walk_all() then also walks every star taken from an inbox in full, and counts where the
  /// two differ (StarWorkTotals::inbox_walk_mismatches).
  void verify_inbox_walks(bool on) { verify_inbox_walks_ = on; }

  /// Site i's walk by box scans into `row`, as the kernels' passes walk it: the full walk, or
  /// the first pass's light one (walk_star_boxes' FirstPass).
  StarWalk walk_site(int i, int* row, unsigned budget, bool first_pass) const {
    if (strips_) {
      if (exact_lattice_)
        return first_pass ? walk_star_by<StarSearch::boxes, true, true, false, true>(grid_, pred_.data(), i, row, budget)
                          : walk_star_by<StarSearch::boxes, true, false, false, true>(grid_, pred_.data(), i, row, budget);
      return first_pass ? walk_star_by<StarSearch::boxes, false, true, false, true>(grid_, pred_.data(), i, row, budget)
                        : walk_star_by<StarSearch::boxes, false, false, false, true>(grid_, pred_.data(), i, row, budget);
    }
    if (exact_lattice_)
      return first_pass ? walk_star_by<StarSearch::boxes, true, true>(grid_, pred_.data(), i, row, budget)
                        : walk_star_by<StarSearch::boxes, true, false>(grid_, pred_.data(), i, row, budget);
    return first_pass ? walk_star_by<StarSearch::boxes, false, true>(grid_, pred_.data(), i, row, budget)
                      : walk_star_by<StarSearch::boxes, false, false>(grid_, pred_.data(), i, row, budget);
  }

  /// The triangles the emit kernel would write after walk_all(), in site ids, read as it reads
  /// them (StarView).
  std::vector<Triangle> owned_triangles_in_site_ids() const {
    std::vector<Triangle> out;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const std::uint32_t inf = info_[i];
      if (star_deferred(inf)) continue;
      const StarView view(star_.data(), inf, static_cast<int>(i));
      for (std::uint32_t m = view.owned_mask(); m != 0u; m &= m - 1u) {
        const int t = std::countr_zero(m);
        out.push_back({to_site_[i], to_site_[view.at(t)], to_site_[view.at(t + 1)]});
      }
    }
    return out;
  }

  /// Local site i's star as walk_all() left it: its row (kStar entries) and info word.
  const int* star_rows() const { return star_.data(); }
  std::uint32_t star_info_of(std::size_t i) const { return info_[i]; }

  /// Work (cells + sites visited) of local site i's last walk by walk_all().
  std::uint32_t site_work(std::size_t i) const { return work_of_[i]; }

  /// Sites in the cell of local site i.
  std::uint32_t cell_occupancy(std::size_t i) const {
    const double2 p = points_[i];
    const std::size_t key = static_cast<std::size_t>(grid_.cell_y(p.y)) * grid_.gx + grid_.cell_x(p.x);
    return cell_start_[key + 1] - cell_start_[key];
  }

  std::size_t site_count() const { return points_.size(); }

  /// Indexed by SiteSet id: whether that site's star deferred.
  std::vector<bool> deferred_sites() const {
    std::vector<bool> out(points_.size());
    for (std::size_t i = 0; i < points_.size(); ++i) out[to_site_[i]] = star_deferred(info_[i]);
    return out;
  }

 private:
  static void fill_guide(const std::vector<double>& bounds, int cells, double lo, double hi, std::vector<int>& table,
                         QuantileGuide& guide) {
    if (!quantile_guided(cells)) return;
    guide.key = build_quantile_guide(bounds.data() + 1, cells, lo, hi, table);
    guide.first = table.data();
  }

  GridView grid_{};
  bool exact_lattice_ = false;  // exact_lattice_arithmetic: walks take the ExactLattice search
  std::vector<double2> points_;
  std::vector<int> to_site_;
  std::vector<std::uint32_t> cell_start_;
  std::vector<double> xb_, yb_;
  std::vector<int> x_guide_, y_guide_;
  std::vector<int> pred_;
  std::vector<int> star_;
  std::vector<std::uint32_t> info_;
  std::vector<std::uint32_t> work_of_;
  bool verify_inbox_walks_ = false;
  bool strips_ = false;
  std::vector<std::uint32_t> strip_keys_;
  std::vector<int> strip_ids_;
  std::array<int, 4> strip_length_{};
  std::vector<std::uint32_t> tail_start_;
  std::vector<int> tail_ids_;
};

}  // namespace expanse::detail::cuda
