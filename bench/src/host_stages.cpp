// The host stages of the pipeline, one at a time: what a GPU backend waits on before and after
// the device runs. One JSON line per (n, stage) with the median, min and max of --reps timed
// runs after one warm-up, the host threads used, and a checksum of the stage's result (equal
// checksums across --threads values show the result does not depend on the thread count).
//
//   expanse-bench-host-stages [--n 1e6,4e6,4096^2] [--dist uniform] [--reps 3] [--threads N]
//                             [--stages prepare,hull,buckets,buckets_coarse,buckets_on_demand,
//                                       audit,derive,seam,output,alloc]
//                             [--open-sites 8] [--cache DIR] [-o FILE.jsonl] [--note TEXT]
//
// Stages:
//   prepare  prepare_sites(points): validate, scale, Morton sort, merge duplicates
//   hull     convex_hull(sites)
//   buckets  BucketTree(sites): what the seam stage searches (buckets_coarse: with 256-site
//            buckets, what the pipeline built for a tiny seam before buckets_on_demand: the
//            start of a tree split only where searches go, what it builds now)
//   audit    adjacency_is_trustworthy() on the full Delaunay triangulation less the triangles
//            around --open-sites sites (a seam like the one a GPU leaves), with its adjacency
//   derive   derive_neighbors() on the same triangles
//   seam     complete_seam() on them (tree built beforehand, not timed), handed over in vectors
//            of exactly their size (seam_reserved: with room for all triangles reserved;
//            seam_coarse: the same over the 256-site-bucket tree; seam_on_demand: over a fresh
//            on-demand tree, its splits included)
//   output   site ids -> input indices over every triangle (the pipeline's output stage)
//   alloc    std::vector resize of the triangles and neighbours a backend downloads into
//            (and alloc_prefaulted: the same through resize_prefaulted; alloc_full: through
//            allocate_full_triangulation, as the CUDA backend does)
//
// The full triangulation comes from the CPU backend's algorithm (the seam stage from one seed)
// and is cached under --cache (default $TMPDIR or /tmp, expanse-host-stages/): building it at
// 16.8M sites takes about a minute on 2 cores.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>

#include "expanse/generate.hpp"
#include "grid/bucket_tree.hpp"
#include "hull/convex_hull.hpp"
#include "input/parallel.hpp"
#include "input/site_set.hpp"
#include "pipeline/output.hpp"
#include "seam/adjacency_audit.hpp"
#include "seam/seam_completion.hpp"
#include "star_host.hpp"
#include "support.hpp"

using namespace expanse;
using namespace expanse::detail;

namespace {

using Clock = std::chrono::steady_clock;

// FNV-1a over 64-bit words, then bytes: a fingerprint of a result, not a secure hash.
struct Checksum {
  std::uint64_t h = 0xcbf29ce484222325ull;
  template <class T, class A>
  Checksum& add(const std::vector<T, A>& v) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(v.data());
    const std::size_t size = v.size() * sizeof(T);
    std::size_t i = 0;
    for (; i + 8 <= size; i += 8) {
      std::uint64_t word;
      std::memcpy(&word, bytes + i, 8);
      h = (h ^ word) * 0x100000001b3ull;
    }
    for (; i < size; ++i) h = (h ^ bytes[i]) * 0x100000001b3ull;
    h = (h ^ size) * 0x100000001b3ull;
    return *this;
  }
  Checksum& add(std::uint64_t word) {
    h = (h ^ word) * 0x100000001b3ull;
    return *this;
  }
  std::string hex() const {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
    return text;
  }
};

// Times `work` once as a warm-up and then `reps` times; `setup` runs untimed before each call.
bench::Summary measure(int reps, const std::function<void()>& setup, const std::function<void()>& work) {
  std::vector<double> samples;
  for (int r = 0; r <= reps; ++r) {
    setup();
    const auto start = Clock::now();
    work();
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    if (r > 0) samples.push_back(ms);
  }
  return bench::summarize(samples);
}

std::filesystem::path default_cache() {
  const char* tmp = std::getenv("TMPDIR");
  return std::filesystem::path(tmp && *tmp ? tmp : "/tmp") / "expanse-host-stages";
}

// The full triangulation of `sites` in site ids, from the cache or made (and cached).
std::vector<Triangle> full_triangulation(const SiteSet& sites, const Hull& hull, const std::filesystem::path& file,
                                         std::uint64_t sites_checksum) {
  const std::size_t expected = 2 * static_cast<std::size_t>(sites.size()) - hull.sites.size() - 2;
  if (std::ifstream in{file, std::ios::binary}) {
    std::uint64_t header[2] = {0, 0};
    in.read(reinterpret_cast<char*>(header), sizeof header);
    if (in && header[0] == sites_checksum && header[1] == expected) {
      std::vector<Triangle> triangles(expected);
      in.read(reinterpret_cast<char*>(triangles.data()), static_cast<std::streamsize>(expected * sizeof(Triangle)));
      if (in) return triangles;
    }
  }
  std::cerr << "building the full triangulation of " << sites.size() << " sites (cached in " << file << ")\n";
  PartialTriangulation mesh;
  {
    const BucketTree tree(sites);
    complete_seam(sites, hull, tree, mesh);
  }
  std::filesystem::create_directories(file.parent_path());
  const auto temporary = file.string() + ".part";
  {
    std::ofstream out{temporary, std::ios::binary};
    const std::uint64_t header[2] = {sites_checksum, expected};
    out.write(reinterpret_cast<const char*>(header), sizeof header);
    out.write(reinterpret_cast<const char*>(mesh.triangles.data()),
              static_cast<std::streamsize>(mesh.triangles.size() * sizeof(Triangle)));
  }
  std::filesystem::rename(temporary, file);
  return std::move(mesh.triangles);
}

// Marks up to `count` sites open: the vertices of the triangles with the largest circumcircles
// (squared radius from the doubles, ranking only), widest first. Near the hull of a uniform
// input these are the long, thin triangles whose searches exceed a GPU's work budget.
void open_widest(const SiteSet& sites, const std::vector<Triangle>& full, std::size_t count, std::vector<bool>& open) {
  std::vector<std::pair<double, std::size_t>> radius(full.size());
  parallel_chunks(full.size(), [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      const Point2 a = sites.points[full[t][0]], b = sites.points[full[t][1]], c = sites.points[full[t][2]];
      const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
      const double d = 2 * (bx * cy - by * cx);
      const double ux = (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / d;
      const double uy = (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / d;
      radius[t] = {-(ux * ux + uy * uy), t};
    }
  });
  const std::size_t keep = std::min(full.size(), 4 * count + 16);
  std::partial_sort(radius.begin(), radius.begin() + static_cast<std::ptrdiff_t>(keep), radius.end());
  std::size_t opened = 0;
  for (std::size_t k = 0; k < keep && opened < count; ++k) {
    for (std::int32_t v : full[radius[k].second]) {
      if (!open[static_cast<std::size_t>(v)] && opened < count) {
        open[static_cast<std::size_t>(v)] = true;
        ++opened;
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Times each host stage of the pipeline"};
  std::vector<std::string> sizes{"1e6", "4e6", "4096^2"};
  std::vector<std::string> stages{"prepare", "hull",   "buckets", "buckets_coarse", "buckets_on_demand", "audit",
                                  "derive",  "seam",   "output",  "alloc"};
  std::string distribution = "uniform", output, note, cache = default_cache().string();
  int reps = 3;
  std::size_t threads = 0, open_sites = 8;
  std::string open_where = "spread";
  std::uint64_t seed = 1;
  app.add_option("--n", sizes, "numbers of points (1e6, 4096^2, ...)")->delimiter(',');
  app.add_option("--dist", distribution, "distribution (expanse generate names)");
  app.add_option("--seed", seed, "generator seed");
  app.add_option("--stages", stages, "stages to time")->delimiter(',');
  app.add_option("--reps", reps, "timed repetitions after one warm-up (median reported)");
  app.add_option("--threads", threads,
                 "host threads for the parallel passes (default: $EXPANSE_HOST_THREADS, else all)");
  app.add_option("--open-sites", open_sites, "sites whose triangles are left out for audit/derive/seam");
  app.add_option("--open-where", open_where,
                 "spread: sites spread over the Morton order; wide: the vertices of the triangles with "
                 "the largest circles (hull-hugging); cuda: the sites the CUDA kernel defers, its "
                 "walks counted on the CPU (--open-sites is then ignored)")
      ->check(CLI::IsMember({"spread", "wide", "cuda"}));
  app.add_option("--cache", cache, "folder for cached full triangulations");
  app.add_option("-o,--output", output, "append JSON lines to this file (default: stdout)");
  app.add_option("--note", note, "free text stored in every record");
  CLI11_PARSE(app, argc, argv);
  if (threads > 0) set_host_threads(threads);

  bench::JsonLinesOutput sink(output);
  std::ostream& out = sink.stream();
  const auto wants = [&](const char* stage) { return std::find(stages.begin(), stages.end(), stage) != stages.end(); };
  const std::string run_id = bench::utc_now();
  const auto machine = bench::machine_info();
  const std::string commit = bench::git_commit();

  for (const std::string& size : sizes) {
    const std::size_t n = bench::parse_count(size);
    const std::vector<Point2> points = generate_points(distribution, n, seed);
    const auto emit = [&](const char* stage, const bench::Summary& s, const std::string& checksum,
                          nlohmann::ordered_json extra = nlohmann::ordered_json::object()) {
      nlohmann::ordered_json record = {
          {"experiment", "host_stages"}, {"run_id", run_id}, {"stage", stage}, {"distribution", distribution},
          {"n", n}, {"threads", host_threads()}, {"median_ms", s.median}, {"min_ms", s.min}, {"max_ms", s.max},
          {"repetitions", reps}, {"checksum", checksum}};
      for (auto& [key, value] : extra.items()) record[key] = value;
      record["commit"] = commit;
      record["date"] = bench::utc_now();
      record["load"] = bench::load_average();
      record["machine"] = machine;
      if (!note.empty()) record["note"] = note;
      out << record.dump() << std::endl;
    };

    std::optional<SiteSet> prepared;
    const auto s_prepare = measure(reps, [&] { prepared.reset(); }, [&] { prepared.emplace(prepare_sites(points)); });
    const SiteSet& sites = *prepared;
    Checksum sites_sum;
    sites_sum.add(sites.points).add(sites.input_index).add(sites.representative).add(std::uint64_t(sites.scale_exponent));
    if (wants("prepare")) emit("prepare", s_prepare, sites_sum.hex(), {{"sites", sites.size()}});

    std::optional<Hull> hulled;
    const auto s_hull = measure(reps, [&] { hulled.reset(); }, [&] { hulled.emplace(convex_hull(sites)); });
    const Hull& hull = *hulled;
    if (wants("hull")) {
      emit("hull", s_hull, Checksum{}.add(hull.sites).add(hull.predecessor).hex(), {{"hull_sites", hull.sites.size()}});
    }

    std::optional<BucketTree> tree;
    if (wants("buckets") || wants("seam")) {
      const auto s = measure(reps, [&] { tree.reset(); }, [&] { tree.emplace(sites); });
      if (wants("buckets")) {
        Checksum sum;
        sum.add(tree->nodes());
        const int side = tree->grid_cells_per_side();
        for (int j = 0; j < side; ++j) {
          for (int i = 0; i < side; ++i) sum.add(static_cast<std::uint64_t>(tree->cell_node(i, j)));
        }
        emit("buckets", s, sum.hex(), {{"nodes", tree->nodes().size()}});
      }
    }

    // The tree the pipeline builds for a tiny seam: buckets of up to 256 sites.
    std::optional<BucketTree> coarse;
    if (wants("buckets_coarse") || wants("seam")) {
      const auto s = measure(reps, [&] { coarse.reset(); }, [&] { coarse.emplace(sites, BucketTree::coarse_capacity); });
      if (wants("buckets_coarse")) {
        emit("buckets_coarse", s, Checksum{}.add(coarse->nodes()).hex(), {{"nodes", coarse->nodes().size()}});
      }
    }

    // The tree the pipeline builds for a tiny seam: made on demand (the stage times its start;
    // its searches split what they enter, inside seam_on_demand).
    if (wants("buckets_on_demand")) {
      std::optional<BucketTree> lazy;
      const auto s = measure(reps, [&] { lazy.reset(); }, [&] { lazy.emplace(BucketTree::on_demand(sites)); });
      emit("buckets_on_demand", s, Checksum{}.add(lazy->nodes()).hex(), {{"nodes", lazy->nodes().size()}});
    }

    if (!(wants("audit") || wants("derive") || wants("seam") || wants("output") || wants("alloc"))) continue;
    const std::filesystem::path cache_file =
        std::filesystem::path(cache) / (distribution + "-" + std::to_string(n) + "-" + std::to_string(seed) + ".tri");
    std::vector<Triangle> full = full_triangulation(sites, hull, cache_file, sites_sum.h);

    // The seam: every triangle touching one of `open_sites` sites, spread over the Morton order
    // or taken from the triangles with the largest circles.
    PartialTriangulation partial;
    {
      std::vector<bool> open(static_cast<std::size_t>(sites.size()), false);
      if (open_where == "spread") {
        for (std::size_t k = 0; k < open_sites; ++k) {
          open[(2 * k + 1) * static_cast<std::size_t>(sites.size()) / (2 * open_sites)] = true;
        }
      } else if (open_where == "wide") {
        open_widest(sites, full, open_sites, open);
      } else {
        cuda::HostStarLayout layout(sites, hull, 2.0, distribution != "uniform" && distribution != "grid");
        layout.walk_all(0, static_cast<unsigned>(host_threads()));
        open = layout.deferred_sites();
      }
      partial.triangles.reserve(full.size());
      for (const Triangle& t : full) {
        if (!open[t[0]] && !open[t[1]] && !open[t[2]]) partial.triangles.push_back(t);
      }
      partial.neighbors = derive_neighbors(partial.triangles);
    }
    const nlohmann::ordered_json seam_info = {{"open_where", open_where},
                                              {"triangles", partial.triangles.size()},
                                              {"left_out", full.size() - partial.triangles.size()}};

    if (wants("audit")) {
      bool trusted = false;
      const auto s = measure(reps, [] {}, [&] { trusted = adjacency_is_trustworthy(partial, hull); });
      if (!trusted) std::cerr << "audit rejected correct adjacency at n = " << n << "\n";
      emit("audit", s, trusted ? "trusted" : "REJECTED", seam_info);
    }
    if (wants("derive")) {
      std::vector<TriangleNeighbors> derived;
      const auto s = measure(
          reps, [&] { std::vector<TriangleNeighbors>().swap(derived); },
          [&] { derived = derive_neighbors(partial.triangles); });
      emit("derive", s, Checksum{}.add(derived).hex(), seam_info);
    }
    if (wants("seam")) {
      PartialTriangulation work;
      SeamStats stats;
      // As a backend hands them over: vectors exactly as large as their contents (the seam
      // stage must move them to make room), or with room for every triangle reserved.
      std::optional<BucketTree> lazy;
      for (const char* variant : {"seam", "seam_reserved", "seam_coarse", "seam_on_demand"}) {
        const bool reserved = variant != std::string("seam");
        const bool on_demand = variant == std::string("seam_on_demand");
        const auto s = measure(
            reps,
            [&] {
              if (on_demand) lazy.emplace(BucketTree::on_demand(sites));  // fresh: searches grow it
              work = PartialTriangulation{};
              if (reserved) {
                work.triangles.reserve(full.size());
                work.neighbors.reserve(full.size());
              }
              work.triangles = partial.triangles;
              work.neighbors = partial.neighbors;
            },
            [&] {
              const BucketTree& search_tree = on_demand ? *lazy : variant == std::string("seam_coarse") ? *coarse : *tree;
              stats = complete_seam(sites, hull, search_tree, work);
            });
        nlohmann::ordered_json info = seam_info;
        info["open_edges"] = stats.open_edges;
        info["triangles_made"] = stats.triangles_made;
        info["candidates_tested"] = stats.candidates_tested;
        info["last_setup_ms"] = stats.setup_ms;  // the phases of the last repetition
        info["last_open_ms"] = stats.open_ms;
        info["last_grow_ms"] = stats.grow_ms;
        if (on_demand) info["nodes"] = lazy->nodes().size();
        emit(variant, s, Checksum{}.add(work.triangles).add(work.neighbors).hex(), info);
      }
    }
    tree.reset();
    coarse.reset();
    if (wants("output")) {
      std::vector<Triangle> triangles;
      const auto s = measure(reps, [&] { triangles = full; }, [&] { remap_to_input(triangles, sites); });
      emit("output", s, Checksum{}.add(triangles).hex(), {{"triangles", full.size()}});
    }
    if (wants("alloc")) {
      std::vector<Triangle> triangles;
      std::vector<TriangleNeighbors> neighbors;
      const auto s = measure(
          reps,
          [&] {
            std::vector<Triangle>().swap(triangles);
            std::vector<TriangleNeighbors>().swap(neighbors);
          },
          [&] {
            triangles.resize(full.size());
            neighbors.resize(full.size());
          });
      emit("alloc", s, "", {{"triangles", full.size()}, {"bytes", 2 * full.size() * sizeof(Triangle)}});
      // The same vectors with their pages faulted in on all threads first (resize_prefaulted).
      const auto p = measure(
          reps,
          [&] {
            std::vector<Triangle>().swap(triangles);
            std::vector<TriangleNeighbors>().swap(neighbors);
          },
          [&] {
            resize_prefaulted(triangles, full.size());
            resize_prefaulted(neighbors, full.size());
          });
      emit("alloc_prefaulted", p, "", {{"triangles", full.size()}, {"bytes", 2 * full.size() * sizeof(Triangle)}});
      // What the CUDA backend calls while its kernel runs: faulted in on all threads, then the
      // two vectors zeroed side by side (allocate_full_triangulation).
      PartialTriangulation room;
      const auto f = measure(
          reps, [&] { room = PartialTriangulation{}; },
          [&] { allocate_full_triangulation(room, static_cast<std::size_t>(sites.size()), hull.sites.size()); });
      emit("alloc_full", f, "", {{"triangles", room.triangles.size()}, {"bytes", 2 * room.triangles.size() * sizeof(Triangle)}});
    }
  }
  return 0;
}
