// expanse-bench: Expanse's backends and the peers triangulate the same points in one run; every
// measured configuration becomes one JSON line (schema in docs/benchmarks.md).
//
// For each distribution and n the points are generated once; then each backend (and, for GPU
// backends, each layout and threads-per-block value) runs `warmup` untimed times and
// `repetitions` timed times. Medians go in the record, with min, max and the raw samples.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <unistd.h>
#include <vector>

#include "expanse/error.hpp"
#include "expanse/generate.hpp"
#include "expanse/mesh.hpp"
#include "expanse/options.hpp"
#include "expanse/picture.hpp"
#include "expanse/triangulate.hpp"
#include "peers.hpp"
#include "support.hpp"

#ifndef EXPANSE_BENCH_DELAUNATOR_SCRIPT
#define EXPANSE_BENCH_DELAUNATOR_SCRIPT ""
#endif

namespace {

// Ordered: stages keep the order they ran in, and records read top-down like the schema.
using json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

struct Config {
  std::string experiment = "adhoc";
  std::vector<std::string> backends;
  std::vector<std::string> distributions;
  std::vector<std::size_t> sizes;
  std::vector<std::string> layouts;
  std::vector<int> threads;
  std::vector<double> sites_per_bucket;  ///< the per-site layout's grid densities to sweep
  int warmup = 1;
  int repetitions = 5;
  double max_seconds = 60.0;
  std::uint64_t seed = 1;
  double scale = 1.0;  ///< generated coordinates times this (0.1: a decimal grid from the integer one)
  int device = -1;
  bool neighbors = true;
  std::string out;
  std::string note;
  std::string command;  // the invocation, stored in every record
  std::string pictures;
  std::string delaunator_script = EXPANSE_BENCH_DELAUNATOR_SCRIPT;
};

// Everything a record shares with every other record of this run.
struct RunContext {
  json machine;
  std::string commit;
  std::string run_id;
  std::ostream* out = nullptr;
};

bool is_expanse_backend(const std::string& name) {
  return name == "cpu" || name == "vulkan" || name == "cuda" || name == "auto";
}

// Why an Expanse backend cannot run here, or nothing when it can.
std::optional<std::string> unavailable(expanse::BackendKind kind) {
  if (kind == expanse::BackendKind::automatic) return std::nullopt;
  for (const auto& backend : expanse::describe_backends()) {
    if (backend.kind != kind) continue;
    if (!backend.compiled) return std::string("not compiled into this build");
    if (backend.devices.empty())
      return backend.unavailable.empty() ? std::string("no device") : backend.unavailable;
    return std::nullopt;
  }
  return std::string("unknown to this build");
}

std::string device_name(expanse::BackendKind kind, int index) {
  for (const auto& backend : expanse::describe_backends()) {
    if (backend.kind != kind || backend.devices.empty()) continue;
    if (index >= 0 && index < static_cast<int>(backend.devices.size()))
      return backend.devices[index].name;
    return backend.devices.front().name;
  }
  return "";
}

json layout_json(const expanse::Layout& layout, const std::string& label) {
  const bool paper = layout.seeding == expanse::Layout::Seeding::paper_blocks;
  return {{"label", label},
          {"seeding", paper ? "paper_blocks" : "per_site"},
          {"blocks_per_side", layout.blocks_per_side},
          {"buckets_per_block_side", layout.buckets_per_block_side},
          {"threads_per_block", layout.threads_per_block},
          {"halo_fraction", layout.halo_fraction},
          {"sites_per_bucket", layout.sites_per_bucket}};
}

json base_record(const RunContext& context, const Config& config, const std::string& backend,
                 const std::string& distribution, std::size_t n) {
  return {{"schema", 1},
          {"experiment", config.experiment},
          {"run_id", context.run_id},
          {"backend", backend},
          {"distribution", distribution},
          {"n", n},
          {"seed", config.seed},
          {"scale", config.scale},
          {"commit", context.commit},
          {"date", bench::utc_now()},
          {"machine", context.machine},
          {"note", config.note},
          {"command", config.command}};
}

void emit(const RunContext& context, json record) {
  record["machine"]["load_average"] = bench::load_average();
  *context.out << record.dump() << '\n';
  context.out->flush();
}

void skip(const RunContext& context, const Config& config, const std::string& backend,
          const std::string& distribution, std::size_t n, const std::string& reason) {
  std::cerr << "  " << backend << ": skipped (" << reason << ")\n";
  auto record = base_record(context, config, backend, distribution, n);
  record["skipped"] = true;
  record["reason"] = reason;
  emit(context, std::move(record));
}

// Repetitions that fit the time budget, judged from the last warm-up run: a 16M-point CPU run
// must not hold a GPU machine for minutes, but one timed run always happens.
int repetitions_within_budget(const Config& config, double warm_ms) {
  if (warm_ms <= 0.0) return config.repetitions;
  const int fit = static_cast<int>(config.max_seconds * 1000.0 / warm_ms);
  return std::max(1, std::min(config.repetitions, fit));
}

// Median of each named stage over the repetitions, in the order of the first repetition.
json stage_medians(const std::vector<std::vector<expanse::StageTime>>& runs) {
  json stages = json::object();
  if (runs.empty()) return stages;
  for (const auto& first : runs.front()) {
    std::vector<double> samples;
    for (const auto& run : runs)
      for (const auto& stage : run)
        if (stage.name == first.name) samples.push_back(stage.ms);
    stages[first.name] = bench::summarize(samples).median;
  }
  return stages;
}

double sum_ms(const std::vector<expanse::StageTime>& stages) {
  double total = 0.0;
  for (const auto& stage : stages) total += stage.ms;
  return total;
}

// Which triangles the seam stage made (1) and which the device's front growth made (0). A Mesh
// with a per-triangle origin is used as is; otherwise the pipeline's current habit of appending
// the seam's triangles after the device's (the CLI relies on it too) splits them by count.
// Empty when neither works: the picture is then drawn in one colour and the record says why.
template <class M>
std::vector<std::uint8_t> triangle_origin(const M& mesh) {
  if constexpr (requires { mesh.triangle_origin; }) {
    return std::vector<std::uint8_t>(mesh.triangle_origin.begin(), mesh.triangle_origin.end());
  } else {
    const auto& s = mesh.stats;
    if (s.gpu_triangles + s.seam_triangles != mesh.triangles.size()) return {};
    std::vector<std::uint8_t> origin(mesh.triangles.size(), 0);
    std::fill(origin.begin() + static_cast<std::ptrdiff_t>(s.gpu_triangles), origin.end(), 1);
    return origin;
  }
}

void run_expanse(const RunContext& context, const Config& config, const std::string& backend,
                 const std::string& distribution, const std::vector<expanse::Point2>& points,
                 std::size_t& reference_triangles) {
  const auto kind = expanse::parse_backend_kind(backend);
  if (auto why = unavailable(kind)) {
    skip(context, config, backend, distribution, points.size(), *why);
    return;
  }
  const bool gpu = kind != expanse::BackendKind::cpu;
  // The CPU backend has no layout: it is the seam stage seeded with one seed.
  std::vector<std::pair<std::string, std::optional<expanse::Layout>>> layouts;
  if (!gpu) {
    layouts.emplace_back("none", std::nullopt);
  } else {
    for (const auto& label : config.layouts) {
      for (int threads : config.threads) {
        for (double density : config.sites_per_bucket) {
          expanse::Layout layout = label == "paper" ? expanse::Layout::paper() : expanse::Layout{};
          layout.threads_per_block = threads;
          if (density > 0) layout.sites_per_bucket = density;
          layouts.emplace_back(label, layout);
        }
      }
    }
  }

  for (const auto& [label, layout] : layouts) {
    expanse::Options options;
    options.backend = kind;
    options.device = config.device;
    options.neighbors = config.neighbors;
    if (layout) options.layout = *layout;

    std::vector<double> totals, walls, device_totals;
    std::vector<std::vector<expanse::StageTime>> stages, device_stages;
    expanse::Mesh mesh;
    try {
      double warm_ms = 0.0;
      for (int i = 0; i < config.warmup; ++i) {
        const auto start = Clock::now();
        mesh = expanse::triangulate(points, options);
        warm_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      }
      const int repetitions = repetitions_within_budget(config, warm_ms);
      for (int i = 0; i < repetitions; ++i) {
        const auto start = Clock::now();
        mesh = expanse::triangulate(points, options);
        walls.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
        totals.push_back(mesh.stats.total_ms);
        stages.push_back(mesh.stats.stages);
        device_stages.push_back(mesh.stats.device_stages);
        if (!mesh.stats.device_stages.empty()) device_totals.push_back(sum_ms(mesh.stats.device_stages));
      }
    } catch (const expanse::Error& e) {
      skip(context, config, backend, distribution, points.size(),
           std::string(expanse::to_string(e.code())) + ": " + e.what());
      continue;
    } catch (const std::exception& e) {
      // Out of memory on a large n, say: record it and go on with the other configurations.
      skip(context, config, backend, distribution, points.size(), std::string("error: ") + e.what());
      continue;
    }

    const auto& s = mesh.stats;
    auto record = base_record(context, config, backend, distribution, points.size());
    record["implementation"] = "expanse";
    record["device"] = s.device.empty() ? device_name(kind, config.device) : s.device;
    record["layout"] = layout ? layout_json(*layout, label) : json(nullptr);
    record["neighbors"] = config.neighbors;
    record["warmup"] = config.warmup;
    record["repetitions"] = static_cast<int>(totals.size());
    record["time_ms"] = {{"total", bench::to_json(bench::summarize(totals))},
                         {"wall", bench::to_json(bench::summarize(walls))}};
    if (!device_totals.empty())
      record["time_ms"]["device"] = bench::to_json(bench::summarize(device_totals));
    record["samples_ms"] = totals;
    record["stages_ms"] = stage_medians(stages);
    record["device_stages_ms"] = stage_medians(device_stages);
    record["sites"] = s.sites;
    record["triangles"] = s.triangles;
    record["gpu_triangles"] = s.gpu_triangles;
    record["seam_triangles"] = s.seam_triangles;
    record["seam_share"] = s.triangles ? double(s.seam_triangles) / double(s.triangles) : 0.0;
    record["iterations"] = s.iterations;
    record["deferred"] = s.deferred_expansions;
    if (reference_triangles == 0) reference_triangles = s.triangles;
    record["triangles_agree"] = s.triangles == reference_triangles;

    std::fprintf(stderr, "  %-10s %-6s threads=%-4d %10.2f ms  seam %5.1f%%  it %zu\n",
                 backend.c_str(), label.c_str(), layout ? layout->threads_per_block : 0,
                 record["time_ms"]["total"]["median"].get<double>(),
                 100.0 * record["seam_share"].get<double>(), s.iterations);
    if (s.triangles != reference_triangles)
      std::fprintf(stderr, "  WARNING: %zu triangles, other backends made %zu\n", s.triangles,
                   reference_triangles);

    if (!config.pictures.empty()) {
      // Figs. IV.4/IV.5: GPU-made and seam-made triangles in different colours.
      expanse::PictureOptions picture;
      picture.triangle_origin = triangle_origin(mesh);
      if (picture.triangle_origin.empty())
        record["picture_note"] = "triangle counts do not add up: origin unknown, one colour";
      const auto stem = std::filesystem::path(config.pictures) /
                        (distribution + "-" + std::to_string(points.size()) + "-" + backend + "-" +
                         label);
      std::filesystem::create_directories(config.pictures);
      // PNG only: results are committed, and `expanse triangulate --svg` redraws any of them.
      expanse::write_png(stem.string() + ".png", points, mesh, picture);
      record["picture"] = stem.string() + ".png";
    }
    emit(context, std::move(record));
  }
}

void record_peer(const RunContext& context, const Config& config, const std::string& backend,
                 const std::string& implementation, const std::string& distribution,
                 std::size_t n, const std::vector<bench::PeerRun>& runs,
                 std::size_t& reference_triangles) {
  std::vector<double> totals;
  std::map<std::string, std::vector<double>> by_stage;
  for (const auto& run : runs) {
    totals.push_back(run.total_ms);
    for (const auto& [name, ms] : run.stages_ms) by_stage[name].push_back(ms);
  }
  auto record = base_record(context, config, backend, distribution, n);
  record["implementation"] = implementation;
  record["device"] = context.machine["cpu"];
  record["layout"] = nullptr;
  record["neighbors"] = true;
  record["warmup"] = config.warmup;
  record["repetitions"] = static_cast<int>(runs.size());
  record["time_ms"] = {{"total", bench::to_json(bench::summarize(totals))}};
  record["samples_ms"] = totals;
  json stages = json::object();
  for (const auto& [name, ms] : runs.front().stages_ms)
    stages[name] = bench::summarize(by_stage[name]).median;
  record["stages_ms"] = stages;
  record["triangles"] = runs.front().triangles;
  if (reference_triangles == 0) reference_triangles = runs.front().triangles;
  record["triangles_agree"] = runs.front().triangles == reference_triangles;
  std::fprintf(stderr, "  %-10s %-6s %-12s %10.2f ms\n", backend.c_str(), "", "",
               record["time_ms"]["total"]["median"].get<double>());
  if (runs.front().triangles != reference_triangles)
    std::fprintf(stderr, "  WARNING: %zu triangles, others made %zu\n", runs.front().triangles,
                 reference_triangles);
  emit(context, std::move(record));
}

template <class F>
void run_in_process_peer(const RunContext& context, const Config& config,
                         const std::string& backend, const std::string& implementation,
                         const std::string& distribution, std::span<const bench::XY> points,
                         F&& triangulate, std::size_t& reference_triangles) {
  std::vector<bench::PeerRun> runs;
  try {
    double warm_ms = 0.0;
    for (int i = 0; i < config.warmup; ++i) warm_ms = triangulate(points).total_ms;
    const int repetitions = repetitions_within_budget(config, warm_ms);
    for (int i = 0; i < repetitions; ++i) runs.push_back(triangulate(points));
  } catch (const std::exception& e) {
    skip(context, config, backend, distribution, points.size(), e.what());
    return;
  }
  record_peer(context, config, backend, implementation, distribution, points.size(), runs,
              reference_triangles);
}

int run(const Config& config) {
  bench::JsonLinesOutput sink(config.out);
  RunContext context;
  context.out = &sink.stream();
  context.machine = bench::machine_info();
  context.commit = bench::git_commit();
  context.run_id = bench::utc_now() + "-" + std::to_string(::getpid());
  std::cerr << "expanse-bench " << config.experiment << ": commit " << context.commit << ", "
            << context.machine["cpu"].get<std::string>() << ", load "
            << json(bench::load_average()).dump() << "\n";

  for (const auto& distribution : config.distributions) {
    for (std::size_t n : config.sizes) {
      std::cerr << distribution << " n=" << n << "\n";
      auto points = expanse::generate_points(distribution, n, config.seed);
      if (config.scale != 1.0)
        for (auto& p : points) p = {p.x * config.scale, p.y * config.scale};
      // The peers read the same coordinates, copied once outside every timing.
      std::vector<bench::XY> xy(points.size());
      for (std::size_t i = 0; i < points.size(); ++i) xy[i] = {points[i].x, points[i].y};
      std::size_t reference_triangles = 0;

      for (const auto& backend : config.backends) {
        if (is_expanse_backend(backend)) {
          run_expanse(context, config, backend, distribution, points, reference_triangles);
        } else if (backend == "cgal") {
          run_in_process_peer(context, config, backend, bench::cgal_version(), distribution, xy,
                              bench::run_cgal, reference_triangles);
        } else if (backend == "qhull") {
          run_in_process_peer(context, config, backend, bench::qhull_version(), distribution, xy,
                              bench::run_qhull, reference_triangles);
        } else if (backend == "delaunator") {
          std::string why_not;
          // One node process per point set: its own warm-up lets the JIT settle first.
          auto runs = bench::run_delaunator(xy, config.warmup, config.repetitions,
                                            config.delaunator_script, why_not);
          if (!runs) {
            skip(context, config, backend, distribution, n, why_not);
            continue;
          }
          record_peer(context, config, backend, runs->version, distribution, n, runs->runs,
                      reference_triangles);
        } else {
          skip(context, config, backend, distribution, n, "unknown backend name");
        }
      }
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Config config;
  std::string backends = "cpu,cgal";
  std::string distributions = "uniform";
  std::string sizes = "1e4";
  std::string layouts = "default";
  std::string threads = "0";
  std::string densities = "0";

  CLI::App app{"Expanse benchmarks: Expanse's backends and peers on the same points, JSON out"};
  app.add_option("--experiment", config.experiment, "label stored in every record (peers, threads, ...)");
  app.add_option("--backends", backends,
                 "comma list of cpu, vulkan, cuda, auto, cgal, qhull, delaunator")
      ->capture_default_str();
  app.add_option("--dist", distributions, "comma list of distributions (expanse generate names)")
      ->capture_default_str();
  app.add_option("-n,--n", sizes, "comma list of sizes: 1000, 1e6, 2^20, 4096^2")->capture_default_str();
  app.add_option("--layouts", layouts, "GPU layouts: default (per-site seeding), paper")
      ->capture_default_str();
  app.add_option("--threads", threads, "GPU threads per block to sweep; 0 = the backend's choice")
      ->capture_default_str();
  app.add_option("--sites-per-bucket", densities,
                 "per-site layout: mean sites per grid cell to sweep; 0 = the layout's default")
      ->capture_default_str();
  app.add_option("--warmup", config.warmup, "untimed runs before the timed ones")->capture_default_str();
  app.add_option("-r,--reps", config.repetitions, "timed repetitions (median reported)")->capture_default_str();
  app.add_option("--max-seconds", config.max_seconds,
                 "fewer repetitions (at least one) when they would take longer than this")
      ->capture_default_str();
  app.add_option("--seed", config.seed, "seed of the point generator")->capture_default_str();
  app.add_option("--scale", config.scale,
                 "multiply the generated coordinates by this (0.1 makes the integer grid a decimal one)")
      ->capture_default_str();
  app.add_option("--device", config.device, "device index for GPU backends; -1 = best")->capture_default_str();
  app.add_flag("!--no-neighbors", config.neighbors, "skip adjacency in Expanse (peers always build it)");
  app.add_option("-o,--out", config.out, "append JSON lines to this file (default: stdout)");
  app.add_option("--note", config.note, "free text stored in every record (e.g. machine load)");
  app.add_option("--pictures", config.pictures, "also write PNG pictures into this folder");
  app.add_option("--delaunator-script", config.delaunator_script, "path of bench/delaunator/run.mjs")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  // What was measured, without where it went or the free-text note.
  config.command = "expanse-bench";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool local = arg == "-o" || arg == "--out" || arg == "--note" || arg == "--pictures" ||
                       arg == "--delaunator-script";
    if (local) {
      ++i;  // and its value
    } else if (arg.rfind("--out=", 0) != 0 && arg.rfind("--note=", 0) != 0 &&
               arg.rfind("--pictures=", 0) != 0 && arg.rfind("--delaunator-script=", 0) != 0) {
      config.command += " " + arg;
    }
  }

  try {
    config.backends = bench::split_list(backends);
    config.distributions = bench::split_list(distributions);
    for (const auto& size : bench::split_list(sizes)) config.sizes.push_back(bench::parse_count(size));
    config.layouts = bench::split_list(layouts);
    for (const auto& t : bench::split_list(threads)) config.threads.push_back(std::stoi(t));
    for (const auto& d : bench::split_list(densities)) config.sites_per_bucket.push_back(std::stod(d));
    for (const auto& layout : config.layouts)
      if (layout != "default" && layout != "paper")
        throw std::invalid_argument("unknown layout " + layout + " (default, paper)");
    return run(config);
  } catch (const std::exception& e) {
    std::cerr << "expanse-bench: " << e.what() << "\n";
    return 2;
  }
}
