// What it costs the host to fault in fresh output storage, the floor under a large
// triangulation's host-to-host time: at 4096^2 the triangles and neighbours are 805 MB of pages
// that the kernel must zero before the download can write them. One JSON line per variant and
// thread count, median / min / max of --reps runs on fresh storage each time:
//   library   prefault_capacity() on two vectors of half the size each (what allocate_full_
//             triangulation does while the device works)
//   populate  MADV_POPULATE_WRITE over the whole buffer in `threads` chunks, with and without
//             asking for transparent huge pages first (huge = 1 / 0)
//   touch     one write per 4 KiB page in `threads` chunks, with and without huge pages
//
//   expanse-bench-page-faults [--mib 805] [--threads 1,2,4,8,16] [--reps 5] [-o FILE.jsonl]
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "input/parallel.hpp"
#include "support/timing.hpp"
#include "support.hpp"

namespace {

using namespace expanse::detail;

struct Page {
  unsigned char bytes[4096];
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Expanse benchmarks: the host's cost of faulting in fresh output storage, JSON out"};
  std::size_t mib = 805;
  std::vector<std::size_t> thread_counts{1, 2, 4, 8, 16};
  int reps = 5;
  std::string output, note;
  app.add_option("--mib", mib, "MiB of storage (805: the triangles and neighbours of 4096^2 points)");
  app.add_option("--threads", thread_counts, "host thread counts to compare")->delimiter(',');
  app.add_option("--reps", reps, "timed repetitions (median reported)");
  app.add_option("-o,--output", output, "append JSON lines to this file (default: stdout)");
  app.add_option("--note", note, "free text stored in every record");
  CLI11_PARSE(app, argc, argv);

  bench::JsonLinesOutput sink(output);
  std::ostream& out = sink.stream();
  const std::size_t pages = (mib << 20) / sizeof(Page);

  const std::string date = bench::utc_now();
  const auto machine = bench::machine_info();
  auto emit = [&](const std::string& variant, std::size_t threads, int huge, std::vector<double> samples) {
    const bench::Summary time = bench::summarize(std::move(samples));
    const nlohmann::ordered_json r = {
        {"benchmark", "page_faults"}, {"variant", variant},     {"threads", threads},
        {"huge_pages", huge},         {"mib", mib},             {"median_ms", time.median},
        {"min_ms", time.min},         {"max_ms", time.max},     {"gb_per_s", double(mib << 20) / 1e6 / time.median},
        {"commit", bench::git_commit()}, {"date", date},        {"machine", machine},
        {"note", note}};
    out << r.dump() << std::endl;
  };

  for (const std::size_t threads : thread_counts) {
    set_host_threads(threads);
    {
      std::vector<double> samples;
      for (int rep = 0; rep < reps; ++rep) {
        // Two vectors of half the size, as the triangles and neighbours.
        std::vector<Page> triangles, neighbors;
        triangles.reserve(pages / 2);
        neighbors.reserve(pages - pages / 2);
        const auto start = Clock::now();
        prefault_capacity(triangles);
        prefault_capacity(neighbors);
        samples.push_back(ms_since(start));
      }
      emit("library", threads, -1, samples);
    }
    for (const bool touch : {false, true})
      for (const int huge : {0, 1}) {
        std::vector<double> samples;
        for (int rep = 0; rep < reps; ++rep) {
          std::vector<Page> storage;
          storage.reserve(pages);
          auto* begin = reinterpret_cast<unsigned char*>(storage.data());
          const auto start = Clock::now();
          if (huge) advise_huge_pages(begin, pages * sizeof(Page));
          parallel_chunks(pages, threads, [&](std::size_t, std::size_t first, std::size_t last) {
            if (!touch && populate_pages(begin + first * sizeof(Page), (last - first) * sizeof(Page))) return;
            for (std::size_t p = first; p < last; ++p) begin[p * sizeof(Page)] = 0;
          });
          samples.push_back(ms_since(start));
        }
        emit(touch ? "touch" : "populate", threads, huge, samples);
      }
  }
  return 0;
}
