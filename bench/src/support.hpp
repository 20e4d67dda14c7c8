#pragma once
// What every benchmark record carries besides its times: where, when, on which commit.
#include <nlohmann/json.hpp>

#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace bench {

/// Median, min and max of repeated measurements. Medians because a shared machine adds
/// one-sided noise (other jobs only ever make a run slower).
struct Summary {
  double median = 0.0;
  double min = 0.0;
  double max = 0.0;
};
Summary summarize(std::vector<double> samples);
nlohmann::ordered_json to_json(const Summary& s);

/// Host name, CPU model, logical cores, memory, compiler: enough to tell machines apart.
nlohmann::ordered_json machine_info();

/// The 1-, 5- and 15-minute load averages: the records say how busy the machine was.
std::vector<double> load_average();

/// The commit measured: $EXPANSE_COMMIT if set, else the commit the programs were built from
/// ("-dirty" when tracked files differed from it at build time).
std::string git_commit();

/// Where a benchmark's JSON lines go: appended to `path` (its folder made if needed), or stdout
/// when the path is empty. A path that cannot be opened ends the program before it measures
/// anything (message on stderr, exit status 2), so that no run's records are silently lost.
class JsonLinesOutput {
 public:
  explicit JsonLinesOutput(const std::string& path);
  std::ostream& stream() { return to_file_ ? static_cast<std::ostream&>(file_) : std::cout; }

 private:
  std::ofstream file_;
  bool to_file_ = false;
};

/// UTC date and time, ISO 8601.
std::string utc_now();

/// Parses "1000", "1e6", "2^20", "4096^2" into a count.
std::size_t parse_count(const std::string& text);

/// Splits "a,b,c" (empty items dropped).
std::vector<std::string> split_list(const std::string& text);

}  // namespace bench
