#pragma once
// What a caller may choose: which backend grows the front, on which device, in which layout.
#include <cstdint>
#include <string>
#include <string_view>

namespace expanse {

enum class BackendKind { automatic, cpu, vulkan, cuda };

/// "auto", "cpu", "vulkan", "cuda".
std::string_view to_string(BackendKind kind) noexcept;
/// Parses the names above; throws Error(invalid_argument) for anything else.
BackendKind parse_backend_kind(std::string_view name);

/// How the GPU backends seed and partition the front growth.
struct Layout {
  enum class Seeding {
    per_site,      ///< every site grows its own star (dense seeding; the default)
    paper_blocks,  ///< the paper: blocks x blocks blocks, one seed each, halo exchange
  };
  Seeding seeding = Seeding::per_site;
  /// Blocks per side of the domain (paper: 16 -> 256 blocks). paper_blocks only.
  int blocks_per_side = 16;
  /// Buckets per side of one block (paper: 16). paper_blocks only.
  int buckets_per_block_side = 16;
  /// Threads (invocations) per block working on its active edges; 0 picks sqrt(n / blocks).
  int threads_per_block = 0;
  /// Width of the halo copied from neighbouring blocks, as a fraction of a block's side.
  double halo_fraction = 0.25;
  /// Mean sites per bucket of the global grid used by per_site seeding. (The CUDA backend's
  /// uniform cells hold 1.75 times as many when the coordinates are not integers:
  /// docs/algorithm.md.)
  double sites_per_bucket = 2.0;

  /// The paper's layout: 16x16 blocks of 16x16 buckets, one seed per block.
  static Layout paper() {
    Layout layout;
    layout.seeding = Seeding::paper_blocks;
    return layout;
  }
};

struct Options {
  BackendKind backend = BackendKind::automatic;
  /// Device index within the backend (as listed by `expanse info`); -1 picks the best one.
  int device = -1;
  /// Compute neighbors (triangle adjacency). Off saves a little time and memory.
  bool neighbors = true;
  Layout layout;
};

}  // namespace expanse
