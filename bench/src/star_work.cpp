// Work the CUDA per-site kernel does, counted on the CPU: the kernel's own search and star walk
// (cuda_backend/star_walk.cuh) run site by site over the same grid, so no GPU is needed.
// Counts, not times: predicates evaluated, cells + sites visited (mean, max, tail), and why
// sites defer to the seam stage. One JSON line per (distribution, n, grid).
// With --first-pass B (box searches), also what the kernel's light first pass (walk_star_boxes'
// FirstPass) does with a budget of B: the sites it hands on to the second pass, for an undecided
// candidate or for running past B, and its predicates. With --by-occupancy, the sites' share and
// work split by how many sites their cell holds. With --emit-views, how many stars the emit's
// links read (StarView loads), a thread a triangle (the kernel) against a thread a site linking
// the triangles it owns, and what lock-step warps of 32 make of each. With --strips, the walks
// scan the grid's boundary strips where those are shorter (BoundaryStrips).
//
//   expanse-bench-star-work [--n 1e6,4e6] [--dist uniform,gaussian,kuzmin] [--grid quantile,uniform]
//                           [--search boxes,rings] [--budget N] [--first-pass B] [--threads 2]
//                           [--by-occupancy] [--emit-views] [--strips] [-o FILE.jsonl] [--note TEXT]
// Records carry the machine, commit and date like expanse-bench's; bench/report.py tabulates them.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <thread>
#include <vector>

#include "expanse/generate.hpp"
#include "input/parallel.hpp"
#include "star_host.hpp"
#include "support.hpp"

namespace {

/// Stars the emit's links read for triangle t of site i (the triangle (i, star t, star t + 1)),
/// as emit_neighbors_kernel reads them: i's own, the star across the edge opposite i (a's, or
/// b's where a deferred), and the owner's of each neighbour that neither of those owns.
int link_views(const int* rows, const std::vector<std::uint32_t>& info, int i, int t) {
  using namespace expanse::detail::cuda;
  const StarView own(rows, info[i], i);
  const int deg = own.degree(), a = own.at(t), b = own.at(t + 1);
  int views = 1;
  if (!star_deferred(info[a]) || !star_deferred(info[b])) {
    ++views;
    const bool at_a = !star_deferred(info[a]);
    const StarView across(rows, info[at_a ? a : b], at_a ? a : b);
    const int p = across.find(at_a ? b : a);
    // As the kernel: an open star has no triangle before its first entry or after its last.
    if (p >= 0 && (across.closed() || (at_a ? p > 0 : p < across.degree() - 1))) {
      const int r = at_a ? across.at(p - 1) : across.at(p + 1);
      const int holder = at_a ? a : b;  // its owned bits are at hand
      if (std::min({a, b, r}) != holder) ++views;
    }
  }
  if (own.closed() || t + 2 < deg) views += !(i < b && i < own.at(t + 2));
  if (own.closed() || t >= 1) views += !(i < own.at(t - 1) && i < a);
  return views;
}

/// The emit's star reads, a thread a triangle (the kernel: warps of 32 consecutive triangles)
/// against a thread a site linking its own triangles (warps of 32 consecutive sites).
nlohmann::ordered_json count_emit_views(const expanse::detail::cuda::HostStarLayout& layout) {
  using namespace expanse::detail::cuda;
  const std::size_t n = layout.site_count();
  std::vector<std::uint32_t> info(n);
  for (std::size_t i = 0; i < n; ++i) info[i] = layout.star_info_of(i);
  const int* rows = layout.star_rows();
  std::uint64_t views = 0, site_views_total = 0, triangles = 0, per_triangle_lockstep = 0, per_site_lockstep = 0;
  int warp_triangle_max = 0, warp_triangles = 0, warp_site_max = 0, warp_sites = 0;
  for (std::size_t s = 0; s < n; ++s) {
    const int i = static_cast<int>(s);
    int site_views = 0;
    if (!star_deferred(info[s])) {
      const StarView own(rows, info[s], i);
      site_views = 1;  // its own star, read once
      for (std::uint32_t m = own.owned_mask(); m != 0u; m &= m - 1u) {
        const int v = link_views(rows, info, i, std::countr_zero(m));
        views += v;
        ++triangles;
        site_views += v - 1;
        warp_triangle_max = std::max(warp_triangle_max, v);
        if (++warp_triangles == 32) {
          per_triangle_lockstep += warp_triangle_max;
          warp_triangle_max = warp_triangles = 0;
        }
      }
    }
    site_views_total += site_views;
    warp_site_max = std::max(warp_site_max, site_views);
    if (++warp_sites == 32) {
      per_site_lockstep += warp_site_max;
      warp_site_max = warp_sites = 0;
    }
  }
  per_triangle_lockstep += warp_triangle_max;
  per_site_lockstep += warp_site_max;
  return {{"triangles", triangles},
          {"views_a_thread_a_triangle", views},
          {"views_a_thread_a_site", site_views_total},
          {"lockstep_views_a_thread_a_triangle", per_triangle_lockstep * 32},
          {"lockstep_views_a_thread_a_site", per_site_lockstep * 32}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Counts the CUDA per-site kernel's work on the CPU"};
  std::vector<std::string> sizes{"1e6"};
  std::string output, note;
  std::vector<std::string> dists{"uniform", "gaussian", "kuzmin"};
  std::vector<std::string> grids{"quantile"};
  std::vector<std::string> searches{"boxes"};
  std::vector<int> phase_counts{1};
  unsigned budget = 0;  // the kernel's default for each search
  unsigned first_pass = 0;  // 0: not counted
  bool by_occupancy = false;
  bool emit_views = false;
  bool strips = false;
  unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  double sites_per_bucket = 2.0;
  app.add_option("--n", sizes, "numbers of points (1e6, 4096^2, ...)")->delimiter(',');
  app.add_option("-o,--output", output, "append JSON lines to this file (default: stdout)");
  app.add_option("--note", note, "free text stored in every record");
  app.add_option("--dist", dists, "distributions (expanse generate names)")->delimiter(',');
  app.add_option("--grid", grids, "quantile and/or uniform")->delimiter(',');
  app.add_option("--search", searches, "boxes and/or rings (cuda_backend/star_scan.cuh)")->delimiter(',');
  app.add_option("--budget", budget, "work units after which a site defers (default: the kernel's)");
  app.add_option("--sites-per-bucket", sites_per_bucket,
                 "mean sites per grid cell (the layout's; CUDA's uniform cells hold 1.75 times as many for non-integer sites)");
  app.add_option("--first-pass", first_pass, "also count the light first pass with this budget (the kernel: 2^10; on quantile cells 2^11 above 2^20 sites, 2^12 above 2^23)");
  app.add_option("--threads", threads, "host threads walking the stars");
  app.add_option("--phases", phase_counts, "phases of the walks: 1, or 2 (boxes only; StarInbox)")
      ->delimiter(',')
      ->check(CLI::IsMember({1, 2}));
  app.add_flag("--by-occupancy", by_occupancy,
               "also split the sites by how many sites their cell holds: share of sites and work a site per class");
  app.add_flag("--strips", strips,
               "walk with the grid's boundary strips (the kernels' edge walks and second pass; BoundaryStrips)");
  app.add_flag("--emit-views", emit_views,
               "also count the stars the emit's links read, a thread a triangle against a thread a site");
  CLI11_PARSE(app, argc, argv);

  bench::JsonLinesOutput sink(output);
  std::ostream& out = sink.stream();
  const std::string run_id = bench::utc_now();
  const auto machine = bench::machine_info();
  for (const std::string& dist : dists) {
    for (const std::string& size : sizes) {
      const std::size_t n = bench::parse_count(size);
      const std::vector<expanse::Point2> points = expanse::generate_points(dist, n, 1);
      const expanse::detail::SiteSet sites = expanse::detail::prepare_sites(points);
      const expanse::detail::Hull hull = expanse::detail::convex_hull(sites);
      for (const std::string& grid : grids) for (const std::string& search : searches) for (const int phases : phase_counts) {
        using expanse::detail::cuda::StarSearch;
        expanse::detail::cuda::HostStarLayout layout(sites, hull, sites_per_bucket, grid == "quantile");
        layout.use_strips(strips);
        const StarSearch kind = search == "rings" ? StarSearch::rings : StarSearch::boxes;
        const auto t = layout.walk_all(budget, threads, kind, phases == 2);
        nlohmann::ordered_json record = {
            {"experiment", "star_work"}, {"run_id", run_id}, {"backend", "cuda-work-count"},
            {"implementation", "expanse"}, {"device", "CUDA per-site kernel, counted on the CPU"},
            {"distribution", dist}, {"n", n}, {"sites", t.sites},
            {"grid", grid}, {"search", search}, {"budget", budget ? budget : expanse::detail::cuda::default_budget(kind)}, {"sites_per_bucket", sites_per_bucket}, {"phases", phases}, {"strips", strips},
            {"predicates_per_site", double(t.predicates) / double(t.sites)},
            {"work_per_site", double(t.work) / double(t.sites)}, {"max_work", t.max_work},
            {"lane_share_8", double(t.work) / (8.0 * double(t.lockstep_work_8))},
            {"lane_share_32", double(t.work) / (32.0 * double(t.lockstep_work_32))},
            {"sites_over_4096", t.sites_over_4096}, {"sites_over_budget", t.sites_over_budget},
            {"sites_over_2^11_to_2^16", t.sites_over_pow2},
            {"deferred", t.deferred}, {"deferred_undecided", t.deferred_undecided},
            {"deferred_full_row", t.deferred_full_row}, {"deferred_no_apex", t.deferred_no_apex},
            {"commit", bench::git_commit()}, {"date", bench::utc_now()}, {"machine", machine}, {"note", note}};
        if (first_pass > 0 && kind == StarSearch::boxes) {
          // Per chunk: handed on (undecided), run past the budget, predicates.
          const std::size_t count = sites.points.size(), chunks = std::max(1u, threads);
          std::vector<std::array<std::uint64_t, 3>> part(chunks, {0, 0, 0});
          expanse::detail::parallel_chunks(count, chunks, [&](std::size_t c, std::size_t begin, std::size_t end) {
            std::array<int, expanse::detail::cuda::kStar> row{};
            for (std::size_t i = begin; i < end; ++i) {
              const auto w = layout.walk_site(static_cast<int>(i), row.data(), first_pass, true);
              part[c][0] += w.handed_on;
              part[c][1] += !w.ok && !w.handed_on && w.work > first_pass;
              part[c][2] += w.predicates;
            }
          });
          std::array<std::uint64_t, 3> sum{0, 0, 0};
          for (const auto& q : part)
            for (int k = 0; k < 3; ++k) sum[k] += q[k];
          record["first_pass"] = {{"budget", first_pass}, {"handed_on", sum[0]}, {"over_budget", sum[1]},
                                  {"predicates_per_site", double(sum[2]) / double(count)}};
        }
        if (by_occupancy) {
          // Classes of cell occupancy 1, 2-3, 4-7, 8-15, ...: how evenly the cells spread the sites,
          // and what a site costs where its cell is emptier or fuller than the mean (quantile cells
          // crowd on the diagonals of a radial density's tail: kuzmin 4096^2 has cells of 2,000).
          std::vector<std::uint64_t> class_sites, class_work;
          for (std::size_t i = 0; i < layout.site_count(); ++i) {
            const std::uint32_t occupancy = layout.cell_occupancy(i);
            std::size_t c = 0;
            while ((2u << c) <= occupancy) ++c;
            if (c >= class_sites.size()) {
              class_sites.resize(c + 1, 0);
              class_work.resize(c + 1, 0);
            }
            ++class_sites[c];
            class_work[c] += layout.site_work(i);
          }
          nlohmann::ordered_json classes = nlohmann::json::array();
          for (std::size_t c = 0; c < class_sites.size(); ++c)
            if (class_sites[c] > 0)
              classes.push_back({{"occupancy_from", 1u << c},
                                 {"occupancy_to", (2u << c) - 1},
                                 {"site_share", double(class_sites[c]) / double(t.sites)},
                                 {"work_per_site", double(class_work[c]) / double(class_sites[c])}});
          record["by_occupancy"] = classes;
        }
        if (emit_views) record["emit_views"] = count_emit_views(layout);
        out << record.dump() << std::endl;
      }
    }
  }
  return 0;
}
