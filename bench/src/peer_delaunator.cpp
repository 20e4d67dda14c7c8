// delaunator runs in node; this side writes the points, runs the script and reads its JSON.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <unistd.h>

#include "peers.hpp"

namespace bench {
namespace {

std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "'\\''";
    else out += c;
  }
  return out + "'";
}

}  // namespace

std::optional<ExternalRuns> run_delaunator(std::span<const XY> points, int warmup, int repetitions,
                                           const std::string& script, std::string& why_not) {
  namespace fs = std::filesystem;
  if (!fs::exists(script)) {
    why_not = "driver script " + script + " not found";
    return std::nullopt;
  }
  if (!fs::exists(fs::path(script).parent_path() / "node_modules" / "delaunator")) {
    why_not = "npm package not installed (run: npm install --prefix " +
              fs::path(script).parent_path().string() + ")";
    return std::nullopt;
  }
  // Little-endian doubles x0 y0 x1 y1 ..., exactly the Float64Array delaunator takes.
  const fs::path file = fs::temp_directory_path() /
                        ("expanse-bench-" + std::to_string(::getpid()) + ".f64");
  {
    std::ofstream out(file, std::ios::binary);
    out.write(reinterpret_cast<const char*>(points.data()),
              static_cast<std::streamsize>(points.size_bytes()));
    if (!out) {
      why_not = "could not write " + file.string();
      return std::nullopt;
    }
  }
  const std::string command = "node --max-old-space-size=16384 " + quote(script) + " " +
                              quote(file.string()) + " " + std::to_string(warmup) + " " +
                              std::to_string(repetitions);
  std::string output;
  int status = -1;
  if (FILE* pipe = ::popen(command.c_str(), "r")) {
    char buffer[4096];
    std::size_t got = 0;
    while ((got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, got);
    status = ::pclose(pipe);
  }
  std::error_code ignored;
  fs::remove(file, ignored);
  if (status != 0) {
    why_not = "node exited with status " + std::to_string(status) + " (" + command + ")";
    return std::nullopt;
  }
  try {
    const auto json = nlohmann::json::parse(output);
    ExternalRuns result;
    result.version = "delaunator " + json.at("delaunator").get<std::string>() + ", node " +
                     json.at("node").get<std::string>();
    const std::size_t triangles = json.at("triangles").get<std::size_t>();
    for (double ms : json.at("samples_ms")) {
      PeerRun run;
      run.stages_ms.emplace_back("triangulate", ms);
      run.total_ms = ms;
      run.triangles = triangles;
      result.runs.push_back(std::move(run));
    }
    return result;
  } catch (const std::exception& e) {
    why_not = std::string("could not read the script's output: ") + e.what();
    return std::nullopt;
  }
}

}  // namespace bench
