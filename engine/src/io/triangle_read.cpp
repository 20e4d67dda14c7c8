// Readers for Triangle's .node, .ele and .neigh files.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "expanse/error.hpp"
#include "expanse/io.hpp"
#include "io/text_scanner.hpp"

namespace expanse {
namespace {

using io_detail::TextScanner;

constexpr std::int64_t kMaxCount = std::numeric_limits<std::int32_t>::max();

std::string plural(std::int64_t n, const char* word) {
  const std::string w = word;
  if (n == 1) return "1 " + w;
  return std::to_string(n) + " " + (w == "vertex" ? std::string("vertices") : w + "s");
}

// The header's first field: how many records follow.
std::int64_t read_count(TextScanner& s, const char* what) {
  std::int64_t count = s.integer(std::string("number of ") + what);
  if (count < 0 || count > kMaxCount) {
    s.fail("number of " + std::string(what) + " " + std::to_string(count) +
           " is outside 0.." + std::to_string(kMaxCount));
  }
  return count;
}

// Optional header fields default as in Triangle.
std::int64_t optional_integer(TextScanner& s, const char* what, std::int64_t fallback) {
  return s.has_field() ? s.integer(what) : fallback;
}

void expect_end_of_header(TextScanner& s) {
  if (s.has_field()) s.fail("unexpected field '" + std::string(s.next_field()) + "' in the header");
}

// A record's leading number: the first fixes the base (0 or 1), the rest must follow on.
std::int64_t record_number(TextScanner& s, std::int64_t i, std::int64_t& first, const char* what) {
  std::int64_t number = s.integer(std::string(what) + " number");
  if (i == 0) {
    if (number != 0 && number != 1) {
      s.fail("first " + std::string(what) + " is numbered " + std::to_string(number) +
             "; numbering must start at 0 or 1");
    }
    first = number;
  } else if (number != first + i) {
    s.fail(std::string(what) + " number " + std::to_string(number) + ", expected " +
           std::to_string(first + i) + " (numbers must be consecutive)");
  }
  return number;
}

void expect_record(TextScanner& s, std::int64_t i, std::int64_t count, std::size_t header_line,
                   const char* what) {
  if (!s.next_line()) {
    s.fail("file ends after " + std::to_string(i) + " of the " + plural(count, what) +
           " declared on line " + std::to_string(header_line));
  }
}

void expect_no_more_records(TextScanner& s, std::int64_t count, std::size_t header_line,
                            const char* what) {
  if (s.next_line()) {
    s.fail("more " + plural(2, what).substr(2) + " than the " + std::to_string(count) +
           " declared on line " + std::to_string(header_line));
  }
}

void check_field_count(TextScanner& s, std::size_t least, std::size_t most,
                       const std::string& layout, std::size_t header_line) {
  std::size_t fields = s.count_fields();
  if (fields < least) {
    s.fail("expected '" + layout + "', found " + plural(static_cast<std::int64_t>(fields), "field"));
  }
  if (fields > most) {
    s.fail(plural(static_cast<std::int64_t>(fields), "field") + ", but the header on line " +
           std::to_string(header_line) + " allows at most " + std::to_string(most) + " ('" +
           layout + "' and its attributes)");
  }
}

}  // namespace

NodeFile read_node_file(const std::filesystem::path& path) {
  const std::string text = io_detail::read_whole_file(path);
  TextScanner s(path.string(), text);
  if (!s.next_line()) {
    s.fail_at(std::max<std::size_t>(1, s.line_number()),
              "no header: expected '<vertices> <dimension> <attributes> <boundary markers>'");
  }
  const std::size_t header_line = s.line_number();
  const std::int64_t count = read_count(s, "vertices");
  const std::int64_t dimension = optional_integer(s, "dimension", 2);
  const std::int64_t attributes = optional_integer(s, "number of attributes", 0);
  const std::int64_t markers = optional_integer(s, "number of boundary markers", 0);
  if (dimension != 2) s.fail("dimension is " + std::to_string(dimension) + "; only 2 is supported");
  if (attributes < 0 || attributes > 1000) s.fail("number of attributes " + std::to_string(attributes) + " is outside 0..1000");
  if (markers != 0 && markers != 1) s.fail("number of boundary markers must be 0 or 1, not " + std::to_string(markers));
  expect_end_of_header(s);

  NodeFile node;
  // A lying header must not allocate gigabytes: a vertex line takes at least 6 bytes.
  node.points.reserve(static_cast<std::size_t>(std::min<std::int64_t>(count, text.size() / 6 + 1)));
  const std::size_t most = 3 + static_cast<std::size_t>(attributes + markers);
  std::int64_t first = 0;
  for (std::int64_t i = 0; i < count; ++i) {
    expect_record(s, i, count, header_line, "vertex");
    check_field_count(s, 3, most, "<vertex #> <x> <y>", header_line);
    const std::int64_t number = record_number(s, i, first, "vertex");
    const double x = s.real("x coordinate");
    const double y = s.real("y coordinate");
    // Attributes and markers are not used, but must still be numbers: a stray word is a mistake.
    while (s.has_field()) s.real("attribute or boundary marker");
    if (!std::isfinite(x) || !std::isfinite(y)) {
      s.fail("point " + std::to_string(number) + " has a non-finite coordinate");
    }
    node.points.push_back({x, y});
  }
  expect_no_more_records(s, count, header_line, "vertex");
  node.first_index = static_cast<int>(first);
  return node;
}

EleFile read_ele_file(const std::filesystem::path& path, int node_first_index) {
  const std::string text = io_detail::read_whole_file(path);
  TextScanner s(path.string(), text);
  if (!s.next_line()) {
    s.fail_at(std::max<std::size_t>(1, s.line_number()),
              "no header: expected '<triangles> <nodes per triangle> <attributes>'");
  }
  const std::size_t header_line = s.line_number();
  const std::int64_t count = read_count(s, "triangles");
  const std::int64_t corners = optional_integer(s, "nodes per triangle", 3);
  const std::int64_t attributes = optional_integer(s, "number of attributes", 0);
  if (corners != 3) s.fail("nodes per triangle is " + std::to_string(corners) + "; only 3 is supported");
  if (attributes < 0 || attributes > 1000) s.fail("number of attributes " + std::to_string(attributes) + " is outside 0..1000");
  expect_end_of_header(s);

  EleFile ele;
  ele.triangles.reserve(static_cast<std::size_t>(std::min<std::int64_t>(count, text.size() / 8 + 1)));
  std::int64_t first = 0;
  for (std::int64_t i = 0; i < count; ++i) {
    expect_record(s, i, count, header_line, "triangle");
    check_field_count(s, 4, 4 + static_cast<std::size_t>(attributes),
                      "<triangle #> <node> <node> <node>", header_line);
    record_number(s, i, first, "triangle");
    Triangle t{};
    for (auto& v : t) {
      const std::int64_t node = s.integer("node number") - node_first_index;
      if (node < 0 || node > kMaxCount) s.fail("node number out of range");
      v = static_cast<std::int32_t>(node);
    }
    while (s.has_field()) s.real("attribute");
    ele.triangles.push_back(t);
  }
  expect_no_more_records(s, count, header_line, "triangle");
  ele.first_index = static_cast<int>(first);
  return ele;
}

std::vector<TriangleNeighbors> read_neigh_file(const std::filesystem::path& path) {
  const std::string text = io_detail::read_whole_file(path);
  TextScanner s(path.string(), text);
  if (!s.next_line()) {
    s.fail_at(std::max<std::size_t>(1, s.line_number()),
              "no header: expected '<triangles> <neighbors per triangle>'");
  }
  const std::size_t header_line = s.line_number();
  const std::int64_t count = read_count(s, "triangles");
  const std::int64_t per = optional_integer(s, "neighbors per triangle", 3);
  if (per != 3) s.fail("neighbors per triangle is " + std::to_string(per) + "; must be 3");
  expect_end_of_header(s);

  std::vector<TriangleNeighbors> neighbors;
  neighbors.reserve(static_cast<std::size_t>(std::min<std::int64_t>(count, text.size() / 8 + 1)));
  std::int64_t first = 0;
  for (std::int64_t i = 0; i < count; ++i) {
    expect_record(s, i, count, header_line, "triangle");
    check_field_count(s, 4, 4, "<triangle #> <neighbor> <neighbor> <neighbor>", header_line);
    record_number(s, i, first, "triangle");
    std::array<std::int32_t, 3> row{};
    for (auto& n : row) {
      const std::int64_t value = s.integer("neighbor");
      if (value == -1) {
        n = no_neighbor;
        continue;
      }
      if (value - first < 0 || value - first >= count) {
        s.fail("neighbor " + std::to_string(value) + " is not a triangle number");
      }
      n = static_cast<std::int32_t>(value - first);
    }
    neighbors.push_back(row);
  }
  expect_no_more_records(s, count, header_line, "triangle");
  return neighbors;
}

}  // namespace expanse
