// The CUDA backend's one reading of the environment (tuning.hpp).
#include "tuning.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace expanse::detail::cuda {
namespace {

const char* env(const char* name) {
  const char* text = std::getenv(name);
  return text && *text ? text : nullptr;
}

bool equals(const char* text, const char* value) { return text && std::strcmp(text, value) == 0; }

std::optional<unsigned> unsigned_of(const char* text) {
  if (!text) return std::nullopt;
  return static_cast<unsigned>(std::strtoul(text, nullptr, 10));
}

Forced forced_of(const char* text) {
  if (equals(text, "0")) return Forced::off;
  if (equals(text, "1")) return Forced::on;
  return Forced::automatic;
}

/// "F,L,E", or "B" for every group (any other text: its first number for every group).
StarBlocks star_blocks_of(const char* text) {
  int v[3] = {0, 0, 0};
  const int got = std::sscanf(text, "%d,%d,%d", &v[0], &v[1], &v[2]);
  return got == 3 ? StarBlocks{v[0], v[1], v[2]} : StarBlocks{v[0], v[0], v[0]};
}

}  // namespace

Tuning tuning_from_environment() {
  Tuning t;
  t.budget = unsigned_of(env("EXPANSE_CUDA_BUDGET"));
  t.first_budget = unsigned_of(env("EXPANSE_CUDA_FIRST_BUDGET"));
  t.retry_budget = unsigned_of(env("EXPANSE_CUDA_RETRY_BUDGET"));
  if (const char* text = env("EXPANSE_CUDA_BLOCKS_PER_SM")) t.blocks_per_sm = star_blocks_of(text);
  if (const char* text = env("EXPANSE_CUDA_PHASES")) t.phases = std::atoi(text) == 2 ? 2 : 1;
  t.strips = forced_of(env("EXPANSE_CUDA_STRIPS"));
  t.tail_columns = forced_of(env("EXPANSE_CUDA_TAIL_COLUMNS"));
  t.tails = parse_tail_weighing(env("EXPANSE_CUDA_TAILS"));
  const char* grid = env("EXPANSE_CUDA_GRID");
  t.grid = equals(grid, "uniform")    ? Tuning::Grid::uniform
           : equals(grid, "quantile") ? Tuning::Grid::quantile
                                      : Tuning::Grid::automatic;
  if (const char* text = env("EXPANSE_CUDA_AUDIT_ROOM")) t.audit_room = std::strtoul(text, nullptr, 10);
  if (const char* text = env("EXPANSE_CUDA_EDGE_RETRY")) {
    if (equals(text, "edge")) {
      t.edge_retry = Tuning::EdgeRetry::edge;
    } else if (std::strncmp(text, "low:", 4) == 0) {
      t.edge_retry = Tuning::EdgeRetry::low;
      const int blocks = std::atoi(text + 4);
      t.edge_retry_blocks_per_sm = blocks > 1 ? blocks : 1;
    }
  }
  const char* sort = env("EXPANSE_CUDA_MORTON_SORT");
  t.morton_sort = equals(sort, "full")    ? Tuning::MortonSort::full
                  : equals(sort, "short") ? Tuning::MortonSort::short_keys
                                          : Tuning::MortonSort::forecast;
  t.prepare_on_device = !equals(env("EXPANSE_CUDA_PREPARE"), "host");
  const char* pin = env("EXPANSE_CUDA_PIN_OUTPUT");
  t.pin_output = pin && !equals(pin, "0");
  t.star_timeline = equals(env("EXPANSE_CUDA_STAR_TIMELINE"), "1");
  return t;
}

}  // namespace expanse::detail::cuda
