// `expanse triangulate`: reads a .node file, triangulates it, and writes .ele (.neigh, pictures).
// Outputs are written only after the triangulation (and --check) succeeded, each atomically;
// if one of them fails, the ones this run already wrote are removed again.
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "expanse/check.hpp"
#include "expanse/error.hpp"
#include "expanse/io.hpp"
#include "expanse/picture.hpp"
#include "expanse/triangulate.hpp"
#include "support/timing.hpp"

namespace expanse::cli {
namespace {

struct TriangulateArgs {
  std::string input;
  std::string prefix;
  std::string backend = "auto";
  int device = -1;
  bool paper = false;
  bool neighbors = false;
  bool svg = false;
  bool png = false;
  bool check = false;
  bool json = false;
  int picture_size = 1024;
};

// Stages may repeat (one per iteration, say): the JSON object sums them under one name.
nlohmann::json stage_object(const std::vector<StageTime>& stages) {
  nlohmann::json object = nlohmann::json::object();
  for (const StageTime& s : stages) {
    object[s.name] = object.contains(s.name) ? object[s.name].get<double>() + s.ms : s.ms;
  }
  return object;
}

std::string stage_list(const std::vector<StageTime>& stages) {
  std::string text;
  char tmp[96];
  for (const StageTime& s : stages) {
    std::snprintf(tmp, sizeof tmp, "%s%s %.2f", text.empty() ? "" : ", ", s.name.c_str(), s.ms);
    text += tmp;
  }
  return text;
}

// Which triangles the seam stage made. The pipeline appends the seam's triangles after the
// device's, so the split is by count; if the counts do not add up, nothing is coloured.
// The CPU backend *is* the seam stage, so colouring all its triangles would say nothing.
std::vector<std::uint8_t> triangle_origin(const Mesh& mesh) {
  const Stats& s = mesh.stats;
  if (s.backend == "cpu" || s.seam_triangles == 0 || s.gpu_triangles + s.seam_triangles != mesh.triangles.size()) return {};
  std::vector<std::uint8_t> origin(mesh.triangles.size(), 0);
  std::fill(origin.begin() + static_cast<std::ptrdiff_t>(s.gpu_triangles), origin.end(), 1);
  return origin;
}

// Files this run has written; removed again unless the run completes.
class OutputSet {
 public:
  ~OutputSet() {
    if (done_) return;
    for (const auto& path : written_) {
      std::error_code ignored;
      std::filesystem::remove(path, ignored);
    }
  }
  template <class Write>
  void add(const std::filesystem::path& path, Write&& write) {
    write(path);
    written_.push_back(path);
  }
  void keep() { done_ = true; }
  const std::vector<std::filesystem::path>& paths() const { return written_; }

 private:
  std::vector<std::filesystem::path> written_;
  bool done_ = false;
};

int run_triangulate(const TriangulateArgs& args) {
  if (args.prefix.empty() && (args.neighbors || args.svg || args.png)) {
    throw Error(ErrorCode::invalid_argument, "--neighbors, --svg and --png need an output prefix (-o)");
  }
  Options options;
  options.backend = parse_backend_kind(args.backend);
  options.device = args.device;
  options.neighbors = args.neighbors || args.check;
  if (args.paper) options.layout = Layout::paper();

  const auto read_start = detail::Clock::now();
  const NodeFile node = read_node_file(args.input);
  const double read_ms = detail::ms_since(read_start);

  Triangulator triangulator(options);
  const Mesh mesh = triangulator.triangulate(node.points);
  const Stats& stats = mesh.stats;

  CheckReport report;
  double check_ms = 0;
  if (args.check) {
    const auto check_start = detail::Clock::now();
    report = check_mesh(node.points, mesh);
    check_ms = detail::ms_since(check_start);
    if (!report.ok) {
      std::fprintf(stderr, "expanse: error: %s: the triangulation failed the check:\n", args.input.c_str());
      for (const std::string& problem : report.problems) std::fprintf(stderr, "  %s\n", problem.c_str());
      return 1;
    }
  }

  const auto write_start = detail::Clock::now();
  OutputSet outputs;
  if (!args.prefix.empty()) {
    const std::string& p = args.prefix;
    outputs.add(p + ".ele", [&](const auto& path) { write_ele_file(path, mesh, node.first_index); });
    if (args.neighbors) {
      outputs.add(p + ".neigh", [&](const auto& path) { write_neigh_file(path, mesh, node.first_index); });
    }
    PictureOptions picture;
    picture.size = args.picture_size;
    picture.triangle_origin = triangle_origin(mesh);
    if (args.svg) outputs.add(p + ".svg", [&](const auto& path) { write_svg(path, node.points, mesh, picture); });
    if (args.png) outputs.add(p + ".png", [&](const auto& path) { write_png(path, node.points, mesh, picture); });
  }
  const double write_ms = detail::ms_since(write_start);

  if (args.json) {
    nlohmann::json out;
    out["input"] = args.input;
    out["input_points"] = stats.input_points;
    out["sites"] = stats.sites;
    out["duplicates"] = stats.duplicates;
    out["hull_sites"] = stats.hull_sites;
    out["triangles"] = stats.triangles;
    out["gpu_triangles"] = stats.gpu_triangles;
    out["seam_triangles"] = stats.seam_triangles;
    out["deferred_expansions"] = stats.deferred_expansions;
    out["iterations"] = stats.iterations;
    out["backend"] = stats.backend;
    out["device"] = stats.device;
    out["layout"] = args.paper ? "paper" : "default";
    out["time_ms"] = {{"total", stats.total_ms},
                      {"stages", stage_object(stats.stages)},
                      {"device_stages", stage_object(stats.device_stages)}};
    out["io_ms"] = {{"read", read_ms}, {"write", write_ms}};
    if (args.check) out["check"] = {{"ok", report.ok}, {"ms", check_ms}};
    out["outputs"] = nlohmann::json::array();
    for (const auto& path : outputs.paths()) out["outputs"].push_back(path.string());
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::string line = std::to_string(stats.sites) + " sites";
    if (stats.duplicates) line += " (" + std::to_string(stats.duplicates) + " duplicates merged)";
    line += ", " + std::to_string(stats.triangles) + " triangles (seam " + std::to_string(stats.seam_triangles);
    if (stats.deferred_expansions) line += ", deferred " + std::to_string(stats.deferred_expansions);
    line += "), " + stats.backend + " on " + stats.device;
    if (stats.iterations) line += ", " + std::to_string(stats.iterations) + " iterations";
    char total[64];
    std::snprintf(total, sizeof total, ": %.2f ms [", stats.total_ms);
    line += total + stage_list(stats.stages) + "]";
    if (!stats.device_stages.empty()) line += " device [" + stage_list(stats.device_stages) + "]";
    if (args.check) line += ", check ok";
    std::printf("%s\n", line.c_str());
  }
  std::fflush(stdout);
  outputs.keep();
  return 0;
}

}  // namespace

Command add_triangulate_command(CLI::App& parent) {
  auto args = std::make_shared<TriangulateArgs>();
  CLI::App* app = parent.add_subcommand(
      "triangulate", "triangulate a .node file; write PREFIX.ele (and .neigh, .svg, .png)");
  app->add_option("input", args->input, "input .node file (Triangle's format)")->required();
  app->add_option("-o,--output", args->prefix,
                  "output prefix: PREFIX.ele etc., numbered from the input's first index; "
                  "without it nothing is written");
  app->add_option("--backend,-b", args->backend, "auto, cpu, vulkan or cuda")
      ->capture_default_str()->check(CLI::IsMember({"auto", "cpu", "vulkan", "cuda"}));
  app->add_option("--device", args->device, "device index within the backend (see `expanse info`); -1: best")
      ->capture_default_str();
  app->add_flag("--paper", args->paper, "the paper's layout: 16x16 blocks of 16x16 buckets, one seed each");
  app->add_flag("--neighbors", args->neighbors, "also write PREFIX.neigh");
  app->add_flag("--svg", args->svg, "also write PREFIX.svg");
  app->add_flag("--png", args->png, "also write PREFIX.png");
  app->add_option("--picture-size", args->picture_size, "longer side of pictures in pixels")
      ->capture_default_str()->check(CLI::Range(16, 16384));
  app->add_flag("--check", args->check, "verify the result exactly; fail (and write nothing) if wrong");
  app->add_flag("--json", args->json, "print one JSON object instead of the summary line");
  return {app, [args] { return run_triangulate(*args); }};
}

}  // namespace expanse::cli
