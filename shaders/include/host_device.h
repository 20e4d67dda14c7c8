// What the shaders and the Vulkan backend's host code share, defined once: push constants,
// specialization-constant ids, counter words, pass ids, the star row and its info word, and the
// sign code `uncertain`. Written in the subset GLSL 4.50 and C++20 have in common; the few
// differences are the macros below. The shaders include it (GL_GOOGLE_include_directive), the
// host code as "host_device.h" (shaders/include is on the library's include path), inside
// namespace expanse::detail::vk::shared.
//
// Layouts: push constants use std430 rules, which C++ reproduces here with a 16-byte aligned
// dvec2; every struct's size is a multiple of 16 and checked on the host (static_assert).
#ifndef EXPANSE_HOST_DEVICE_H
#define EXPANSE_HOST_DEVICE_H

#ifdef __cplusplus
#include <cstdint>

#include "predicates/exact_arith.hpp"
namespace expanse::detail::vk::shared {
using uint = std::uint32_t;
struct alignas(16) dvec2 {
  double x = 0.0, y = 0.0;
};
#define EXPANSE_SHARED_CONST inline constexpr
#define EXPANSE_SHARED_FN inline constexpr
#else
#define EXPANSE_SHARED_CONST const
#define EXPANSE_SHARED_FN
#endif

// ---- The sign code "the filter could not decide" ---------------------------------------------
// C++ has it as expanse::exact::uncertain; the shaders get the same value under the same name.
#define EXPANSE_UNCERTAIN 2
#ifdef __cplusplus
static_assert(EXPANSE_UNCERTAIN == exact::uncertain);
#else
const int uncertain = EXPANSE_UNCERTAIN;
#endif

// ---- Counter words ----------------------------------------------------------------------------
// One buffer of 16 uints per growth, shared by the passes of a submission.
EXPANSE_SHARED_CONST int COUNTER_WORDS = 16;
EXPANSE_SHARED_CONST int COUNTER_TRIANGLES = 0;   // triangles written (star.comp, blocks.comp)
EXPANSE_SHARED_CONST int COUNTER_DEFERRED = 1;    // deferred sites (star) or expansions (blocks)
EXPANSE_SHARED_CONST int COUNTER_OVERFLOW = 2;    // the triangle output overflowed its capacity
EXPANSE_SHARED_CONST int COUNTER_IMPOSSIBLE = 3;  // star.comp: a search found no candidate anywhere
EXPANSE_SHARED_CONST int COUNTER_BLOCK_ITERATIONS = 3;       // blocks.comp: most iterations of a block
EXPANSE_SHARED_CONST int COUNTER_BLOCK_OPEN = 4;             // blocks.comp: edges left to the seam
EXPANSE_SHARED_CONST int COUNTER_BLOCK_ACTIVE_OVERFLOW = 5;  // blocks.comp: active lists overflowed
EXPANSE_SHARED_CONST int COUNTER_UNRESOLVED = 4;           // star_links.comp: unresolved slots listed
EXPANSE_SHARED_CONST int COUNTER_LINKS_CUT = 5;            // star_links.comp: loop cap hit (links void)
EXPANSE_SHARED_CONST int COUNTER_UNRESOLVED_OVERFLOW = 6;  // star_links.comp: too many unresolved
EXPANSE_SHARED_CONST int COUNTER_CROWDED_CELL = 8;  // bucket.comp: a cell too large to rank
EXPANSE_SHARED_CONST int COUNTER_INVALID_ID = 9;    // bucket.comp's restore: an id out of range
EXPANSE_SHARED_CONST int COUNTER_BAD_LINKS = 10;     // audit.comp: links that do not lead back
EXPANSE_SHARED_CONST int COUNTER_OPEN_EDGES = 11;    // audit.comp: open edges inside the hull
EXPANSE_SHARED_CONST int COUNTER_OPEN_OVERFLOW = 12; // audit.comp: open edges not listed
// prepare_sites.comp's own counter buffer.
EXPANSE_SHARED_CONST int PREPARE_COUNTER_LONG_RUN = 0;  // a run of equal codes too long to search
EXPANSE_SHARED_CONST int PREPARE_COUNTER_SITES = 1;     // the sites after merging duplicates

// ---- Stars (star.comp writes them, star_links.comp and the host read them) ---------------------
// The star of s is row s of STAR_ROW ints, counter-clockwise from index star_start, wrapping.
// Per-site info packs
//   bits 0-4 degree, bits 5-8 start index in the row, STAR_CLOSED, STAR_DEFERRED (bit 11 with
//   it: STAR_HANDED_ON, between the first pass and its retry),
//   bits 16-31: bit t set when s owns its t-th star triangle (s smallest of its three sites).
EXPANSE_SHARED_CONST int STAR_ROW = 16;
EXPANSE_SHARED_CONST uint STAR_CLOSED = 1u << 9;
EXPANSE_SHARED_CONST uint STAR_DEFERRED = 1u << 10;
// Left by the first pass for the retry (star.comp's EXACT_PATH): deferred, so far.
EXPANSE_SHARED_CONST uint STAR_HANDED_ON = STAR_DEFERRED | (1u << 11);

EXPANSE_SHARED_FN uint star_info(int degree, int start, bool closed) {
  return uint(degree) | (uint(start) << 5) | (closed ? STAR_CLOSED : 0u);
}
EXPANSE_SHARED_FN int star_degree(uint info) { return int(info & 31u); }
EXPANSE_SHARED_FN int star_start(uint info) { return int((info >> 5) & 15u); }
EXPANSE_SHARED_FN bool star_closed(uint info) { return (info & STAR_CLOSED) != 0u; }
EXPANSE_SHARED_FN bool star_deferred(uint info) { return (info & STAR_DEFERRED) != 0u; }
EXPANSE_SHARED_FN bool star_handed_on(uint info) { return info == STAR_HANDED_ON; }
EXPANSE_SHARED_FN uint star_owned(uint info) { return info >> 16; }
// Number of triangles in the star (one less than the degree when it meets the hull).
EXPANSE_SHARED_FN int star_triangles(uint info) {
  return star_closed(info) ? star_degree(info) : star_degree(info) - 1;
}

// star.comp's specialization constants (local_size_x_id = 0: the workgroup size).
#define STAR_SPEC_WORKGROUP 0
#define STAR_SPEC_CAPACITY 1
#define STAR_SPEC_LOOP_BUDGET 2
#define STAR_SPEC_APEX_FILTERS 3
#define STAR_SPEC_EXACT_LATTICE 4
#define STAR_SPEC_QUANTILE_CELLS 5
#define STAR_SPEC_EXACT_PATH 6
#define STAR_SPEC_RETRY 7
#define STAR_SPEC_EXACT_DIFFERENCES 8
#define STAR_SPEC_EDGE_PART 9
#define STAR_SPEC_COUNT 10
// star_links.comp's.
#define LINKS_SPEC_WORKGROUP 0
#define LINKS_SPEC_CAPACITY 1
#define LINKS_SPEC_COUNT 2

// star.comp's push constants.
struct StarParams {
  dvec2 origin;
  dvec2 inv_width;
  int cells;
  int site_count;
  int first_site;  // dispatches are split to respect maxComputeWorkGroupCount
  int triangle_capacity;
  // A scan of more cells than this stops at the first better candidate, to plan a smaller box.
  int big_scan_cells;
  // Phases (docs/algorithm.md): the sites are split into phase_count phases by their ids
  // (phase_count a power of two, id i in phase i % phase_count) and walked phase by phase;
  // this dispatch walks phase `phase`. A site takes every triangle it shares with a site of an
  // earlier phase from what that site's star posted to its inbox, and searches for the rest.
  int phase;
  int phase_count;
  int pad;
};

// star_links.comp's push constants.
struct LinkParams {
  int site_count;
  int first_site;
  int unresolved_capacity;
  int pad;
};

// ---- Paper blocks (blocks.comp) ---------------------------------------------------------------
struct BlockParams {
  dvec2 origin;
  dvec2 inv_width;
  int cells;
  int block_count;
  int first_block;  // dispatches are split to respect maxComputeWorkGroupCount
  int triangle_capacity;
};
// Per block, BLOCK_INFO_WORDS ints of the block list: the extended cell range, where its cells
// and sites start in the block-local lists, its local site count and seed, and its slices of the
// edge sets and active lists.
EXPANSE_SHARED_CONST int BLOCK_INFO_WORDS = 12;
EXPANSE_SHARED_CONST int BLOCK_LO_X = 0;
EXPANSE_SHARED_CONST int BLOCK_LO_Y = 1;
EXPANSE_SHARED_CONST int BLOCK_HI_X = 2;
EXPANSE_SHARED_CONST int BLOCK_HI_Y = 3;
EXPANSE_SHARED_CONST int BLOCK_CELL_BASE = 4;
EXPANSE_SHARED_CONST int BLOCK_SLOT_BASE = 5;
EXPANSE_SHARED_CONST int BLOCK_SITE_COUNT = 6;
EXPANSE_SHARED_CONST int BLOCK_SEED_SLOT = 7;
EXPANSE_SHARED_CONST int BLOCK_HASH_BASE = 8;
EXPANSE_SHARED_CONST int BLOCK_HASH_CAPACITY = 9;
EXPANSE_SHARED_CONST int BLOCK_ACTIVE_BASE = 10;
EXPANSE_SHARED_CONST int BLOCK_ACTIVE_CAPACITY = 11;

// ---- Audit (audit.comp) -----------------------------------------------------------------------
struct AuditParams {
  int triangle_capacity;
  int open_capacity;
  int first;  // dispatches are split to respect maxComputeWorkGroupCount
  int pad;
};

// ---- Bucketing (bucket.comp) ------------------------------------------------------------------
struct BucketParams {
  dvec2 origin;
  dvec2 inv_width;
  int cells;
  int count;  // sites
  int first;  // dispatches are split to respect maxComputeWorkGroupCount
  int pass;
  int triangle_capacity;
  int pad0;
  int pad1;
  int pad2;
};
EXPANSE_SHARED_CONST int BUCKET_PASS_COUNT = 0;
EXPANSE_SHARED_CONST int BUCKET_PASS_SCATTER = 1;
EXPANSE_SHARED_CONST int BUCKET_PASS_ORDER = 2;
EXPANSE_SHARED_CONST int BUCKET_PASS_PREDECESSOR = 3;
EXPANSE_SHARED_CONST int BUCKET_PASS_RESTORE = 4;
#define BUCKET_SPEC_WORKGROUP 0
#define BUCKET_SPEC_MAX_CELL 1
#define BUCKET_SPEC_QUANTILE_CELLS 2
#define BUCKET_SPEC_COUNT 3

// ---- Prefix sums (scan.comp) ------------------------------------------------------------------
struct ScanParams {
  int count;          // elements of this level
  int offset;         // where this level starts (in sums when level_in_sums != 0)
  int level_in_sums;
  int sums_offset;    // where the next level (one total per tile) starts in sums
  int first_tile;     // dispatches are split to respect maxComputeWorkGroupCount
  int pass;
  int pad0;
  int pad1;
};
EXPANSE_SHARED_CONST int SCAN_PASS_TILES = 0;
EXPANSE_SHARED_CONST int SCAN_PASS_ADD = 1;
EXPANSE_SHARED_CONST int SCAN_PER_THREAD = 4;  // elements each invocation scans

// ---- Site preparation (prepare_sites.comp, radix_sort.comp) -----------------------------------
struct PrepareParams {
  dvec2 origin;          // the Quantiser's
  double scale;          // the Quantiser's
  double factor;         // the scale: p * factor * second_factor, both powers of two, each exact
  double second_factor;
  int count;             // points (PREPARE_PASS_HULL, PREPARE_PASS_PREDECESSOR: hull sites)
  int pass;
  int first;             // dispatches are split to respect maxComputeWorkGroupCount
  int side;              // where the sorted keys and input indices are
  int mode;              // PREPARE_PASS_KEYS: which key; PREPARE_PASS_SAMPLE: the stride
  int pad;
};
EXPANSE_SHARED_CONST int PREPARE_PASS_CODES = 0;
EXPANSE_SHARED_CONST int PREPARE_PASS_GATHER = 1;
EXPANSE_SHARED_CONST int PREPARE_PASS_FIRST_EQUAL = 2;
EXPANSE_SHARED_CONST int PREPARE_PASS_KEYS = 3;
EXPANSE_SHARED_CONST int PREPARE_PASS_GROUP_START = 4;
EXPANSE_SHARED_CONST int PREPARE_PASS_HEAD_POSITION = 5;
EXPANSE_SHARED_CONST int PREPARE_PASS_FIRST_OF_GROUP = 6;
EXPANSE_SHARED_CONST int PREPARE_PASS_COMPACT = 7;
EXPANSE_SHARED_CONST int PREPARE_PASS_HULL = 8;
EXPANSE_SHARED_CONST int PREPARE_PASS_PREDECESSOR = 9;
EXPANSE_SHARED_CONST int PREPARE_PASS_SAMPLE = 10;

struct RadixParams {
  int count;       // elements
  int tiles;       // (count + tile - 1) / tile
  int shift;       // of this pass's digit in the 64-bit key
  int side;        // the side this pass reads
  int first_tile;  // dispatches are split to respect maxComputeWorkGroupCount
  int pass;
  int pad0;
  int pad1;
};
EXPANSE_SHARED_CONST int RADIX_PASS_COUNT = 0;
EXPANSE_SHARED_CONST int RADIX_PASS_SCATTER = 1;
EXPANSE_SHARED_CONST int RADIX_ITEMS = 8;   // keys each invocation sorts
EXPANSE_SHARED_CONST int RADIX_DIGITS = 16; // digits of a pass (4 bits)

// ---- Predicate test (predicate_test.comp) -----------------------------------------------------
struct PredicateTestParams {
  int count;
  int pad0;
  int pad1;
  int pad2;
};
EXPANSE_SHARED_CONST int PREDICATE_TEST_SIGNS = 12;  // signs per case
EXPANSE_SHARED_CONST int PREDICATE_TEST_EFT = 4;     // doubles per case

#ifdef __cplusplus
static_assert(sizeof(StarParams) == 64 && sizeof(LinkParams) == 16 && sizeof(BlockParams) == 48);
static_assert(sizeof(AuditParams) == 16 && sizeof(BucketParams) == 64 && sizeof(ScanParams) == 32);
static_assert(sizeof(PrepareParams) == 64 && sizeof(RadixParams) == 32 && sizeof(PredicateTestParams) == 16);
}  // namespace expanse::detail::vk::shared
#endif

#endif
