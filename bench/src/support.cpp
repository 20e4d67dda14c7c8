#include "support.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace bench {

const char* build_commit();  // generated at build time (bench/cmake/commit.cmake)

namespace {

std::string proc_field(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) == 0) {
      auto colon = line.find(':');
      if (colon == std::string::npos) continue;
      auto value = line.substr(colon + 1);
      value.erase(0, value.find_first_not_of(" \t"));
      return value;
    }
  }
  return {};
}

}  // namespace

Summary summarize(std::vector<double> samples) {
  if (samples.empty()) return {};
  std::sort(samples.begin(), samples.end());
  const std::size_t n = samples.size();
  const double median = n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
  return {median, samples.front(), samples.back()};
}

nlohmann::ordered_json to_json(const Summary& s) {
  return {{"median", s.median}, {"min", s.min}, {"max", s.max}};
}

nlohmann::ordered_json machine_info() {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  nlohmann::ordered_json info;
  info["hostname"] = host;
  info["cpu"] = proc_field("/proc/cpuinfo", "model name");
  info["logical_cores"] = std::thread::hardware_concurrency();
  info["memory"] = proc_field("/proc/meminfo", "MemTotal");
#if defined(__clang__)
  info["compiler"] = std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  info["compiler"] = std::string("gcc ") + __VERSION__;
#endif
  return info;
}

std::vector<double> load_average() {
  double load[3] = {0, 0, 0};
  if (::getloadavg(load, 3) != 3) return {};
  return {load[0], load[1], load[2]};
}

std::string git_commit() {
  if (const char* forced = std::getenv("EXPANSE_COMMIT"); forced && *forced) return forced;
  return build_commit();
}

JsonLinesOutput::JsonLinesOutput(const std::string& path) : to_file_(!path.empty()) {
  if (!to_file_) return;
  std::error_code ignored;  // a folder that cannot be made shows as the open's failure
  if (const auto parent = std::filesystem::path(path).parent_path(); !parent.empty())
    std::filesystem::create_directories(parent, ignored);
  file_.open(path, std::ios::app);
  if (!file_) {
    std::cerr << "cannot open " << path << " to append JSON lines\n";
    std::exit(2);
  }
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

std::size_t parse_count(const std::string& text) {
  if (auto caret = text.find('^'); caret != std::string::npos) {
    const double base = std::stod(text.substr(0, caret));
    const double exponent = std::stod(text.substr(caret + 1));
    return static_cast<std::size_t>(std::llround(std::pow(base, exponent)));
  }
  std::size_t used = 0;
  const double value = std::stod(text, &used);
  if (used != text.size() || value < 0) throw std::invalid_argument("not a count: " + text);
  return static_cast<std::size_t>(std::llround(value));
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) items.push_back(item);
  return items;
}

}  // namespace bench
