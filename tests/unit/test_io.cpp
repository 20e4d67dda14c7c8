// Triangle file formats and pictures: parsing, error messages with FILE:LINE, round trips,
// atomic writes.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>

#include "expanse/error.hpp"
#include "expanse/io.hpp"
#include "expanse/picture.hpp"

namespace fs = std::filesystem;
using expanse::Error;
using expanse::ErrorCode;
using expanse::Point2;

namespace {

// A fresh directory per test case, removed afterwards.
struct TempDir {
  fs::path path;
  TempDir() {
    static int counter = 0;
    path = fs::temp_directory_path() /
           ("expanse_test_io_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    fs::path file = path / name;
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }
  std::size_t entries() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(path), fs::directory_iterator()));
  }
};

// The message of the Error thrown by f, checked to carry `code`.
template <class F>
std::string error_of(F&& f, ErrorCode code) {
  try {
    f();
  } catch (const Error& e) {
    CHECK(e.code() == code);
    return e.what();
  }
  FAIL("no expanse::Error thrown");
  return {};
}

expanse::Mesh two_triangles() {
  expanse::Mesh mesh;
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.neighbors = {{-1, 1, -1}, {-1, -1, 0}};
  mesh.hull = {0, 1, 2, 3};
  return mesh;
}

const std::vector<Point2> kSquare = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

}  // namespace

TEST_CASE("read_node_file reads a 0-based file with comments and blank lines", "[io]") {
  TempDir dir;
  auto file = dir.write("a.node",
                        "# a comment\n"
                        "\n"
                        "3 2 0 0   # header comment\n"
                        "0 0.5 -1.25\n"
                        "   \t\n"
                        "1 1e3 +2\n"
                        "# between\n"
                        "2 -0 3.0e-5\r\n");
  auto node = expanse::read_node_file(file);
  CHECK(node.first_index == 0);
  REQUIRE(node.points.size() == 3);
  CHECK(node.points[0] == Point2{0.5, -1.25});
  CHECK(node.points[1] == Point2{1000.0, 2.0});
  CHECK(node.points[2] == Point2{-0.0, 3.0e-5});
}

TEST_CASE("read_node_file reads a 1-based file with attributes and markers", "[io]") {
  TempDir dir;
  auto file = dir.write("b.node", "2 2 2 1\n1 10 20 0.5 7 1\n2 30 40 0.25 8 0\n");
  auto node = expanse::read_node_file(file);
  CHECK(node.first_index == 1);
  REQUIRE(node.points.size() == 2);
  CHECK(node.points[1] == Point2{30, 40});
}

TEST_CASE("read_node_file accepts a header with only the count, and an empty set", "[io]") {
  TempDir dir;
  CHECK(expanse::read_node_file(dir.write("c.node", "1\n1 2 3\n")).points.size() == 1);
  CHECK(expanse::read_node_file(dir.write("d.node", "0 2 0 0\n")).points.empty());
}

TEST_CASE("read_node_file names FILE:LINE for malformed content", "[io]") {
  TempDir dir;
  struct Case {
    const char* text;
    const char* expected;  // after "FILE:"
  };
  const Case cases[] = {
      {"", "1: no header"},
      {"2 2 0 0\n0 1 2\n1 1 x\n", "3: y coordinate 'x' is not a number"},
      {"2 2 0 0\n0 1 2\n1 1\n", "3: expected '<vertex #> <x> <y>', found 2 fields"},
      {"2 2 0 0\n0 1 2\n1 1 2 3\n", "3: 4 fields, but the header on line 1 allows at most 3"},
      {"3 2 0 0\n0 1 2\n\n1 1 2\n", "4: file ends after 2 of the 3 vertices declared on line 1"},
      {"1 2 0 0\n0 1 2\n1 1 2\n", "3: more vertices than the 1 declared on line 1"},
      {"2 3 0 0\n", "1: dimension is 3"},
      {"2 2 0 0\n5 1 2\n", "2: first vertex is numbered 5"},
      {"3 2 0 0\n1 1 2\n2 1 2\n4 1 2\n", "4: vertex number 4, expected 3"},
      {"-1 2 0 0\n", "1: number of vertices -1 is outside"},
      {"x\n", "1: number of vertices 'x' is not an integer"},
      {"2 2 0 0\n0 1 2\n1 1e999 2\n", "3: x coordinate '1e999' is out of the range of a double"},
      {"1 2 0 2\n", "1: number of boundary markers must be 0 or 1"},
      {"1 2 0 0 9\n", "1: unexpected field '9' in the header"},
  };
  for (const Case& c : cases) {
    INFO(c.text);
    auto file = dir.write("bad.node", c.text);
    const std::string message = error_of([&] { expanse::read_node_file(file); }, ErrorCode::parse_error);
    CHECK(message.rfind(file.string() + ":" + c.expected, 0) == 0);
  }
}

TEST_CASE("read_node_file rejects non-finite coordinates naming the point", "[io]") {
  TempDir dir;
  auto file = dir.write("nan.node", "# header next\n3 2 0 0\n1 0 0\n2 nan 1\n3 1 1\n");
  CHECK(error_of([&] { expanse::read_node_file(file); }, ErrorCode::parse_error) ==
        file.string() + ":4: point 2 has a non-finite coordinate");
  auto inf = dir.write("inf.node", "2 2 0 0\n0 0 0\n1 1 -inf\n");
  CHECK(error_of([&] { expanse::read_node_file(inf); }, ErrorCode::parse_error) ==
        inf.string() + ":3: point 1 has a non-finite coordinate");
}

TEST_CASE("read_node_file reports a missing file as io_error", "[io]") {
  TempDir dir;
  const std::string message =
      error_of([&] { expanse::read_node_file(dir.path / "missing.node"); }, ErrorCode::io_error);
  CHECK(message.find("missing.node") != std::string::npos);
}

TEST_CASE("node files round-trip every double exactly", "[io]") {
  TempDir dir;
  std::mt19937_64 bits(42);
  std::vector<Point2> points;
  for (int i = 0; i < 2000; ++i) {
    double x, y;
    do {
      auto a = bits(), b = bits();
      std::memcpy(&x, &a, sizeof x);
      std::memcpy(&y, &b, sizeof y);
    } while (!std::isfinite(x) || !std::isfinite(y));
    points.push_back({x, y});
  }
  points.push_back({std::numeric_limits<double>::denorm_min(), -std::numeric_limits<double>::max()});
  points.push_back({0.1, 1e-300});
  for (int base : {0, 1}) {
    auto file = dir.path / ("rt" + std::to_string(base) + ".node");
    expanse::write_node_file(file, points, base);
    auto node = expanse::read_node_file(file);
    CHECK(node.first_index == base);
    REQUIRE(node.points.size() == points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      CHECK(std::memcmp(&node.points[i], &points[i], sizeof(Point2)) == 0);
    }
  }
}

TEST_CASE("ele and neigh files use the index base and keep -1", "[io]") {
  TempDir dir;
  const expanse::Mesh mesh = two_triangles();
  expanse::write_ele_file(dir.path / "m.ele", mesh, 1);
  expanse::write_neigh_file(dir.path / "m.neigh", mesh, 1);
  std::ifstream ele(dir.path / "m.ele");
  std::string text((std::istreambuf_iterator<char>(ele)), {});
  CHECK(text == "2 3 0\n1 1 2 3\n2 1 3 4\n");
  std::ifstream neigh(dir.path / "m.neigh");
  std::string ntext((std::istreambuf_iterator<char>(neigh)), {});
  CHECK(ntext == "2 3\n1 -1 2 -1\n2 -1 -1 1\n");

  for (int base : {0, 1}) {
    expanse::write_ele_file(dir.path / "r.ele", mesh, base);
    expanse::write_neigh_file(dir.path / "r.neigh", mesh, base);
    auto back = expanse::read_ele_file(dir.path / "r.ele", base);
    CHECK(back.first_index == base);
    CHECK(back.triangles == mesh.triangles);
    CHECK(expanse::read_neigh_file(dir.path / "r.neigh") == mesh.neighbors);
  }
}

TEST_CASE("writers leave no file behind on failure", "[io]") {
  TempDir dir;
  expanse::Mesh no_neighbors = two_triangles();
  no_neighbors.neighbors.clear();
  error_of([&] { expanse::write_neigh_file(dir.path / "x.neigh", no_neighbors, 0); },
           ErrorCode::invalid_argument);
  error_of([&] { expanse::write_ele_file(dir.path / "x.ele", two_triangles(), 2); },
           ErrorCode::invalid_argument);
  // A directory that does not exist: the temporary file cannot even be created.
  error_of([&] { expanse::write_node_file(dir.path / "nowhere" / "x.node", kSquare); },
           ErrorCode::io_error);
  // A bad picture option is found before anything is written.
  expanse::PictureOptions options;
  options.triangle_origin = {0};
  error_of([&] { expanse::write_svg(dir.path / "x.svg", kSquare, two_triangles(), options); },
           ErrorCode::invalid_argument);
  error_of([&] { expanse::write_png(dir.path / "x.png", kSquare, two_triangles(), options); },
           ErrorCode::invalid_argument);
  CHECK(dir.entries() == 0);
}

TEST_CASE("a failed rename leaves neither the target nor a temporary file", "[io]") {
  TempDir dir;
  fs::create_directories(dir.path / "occupied.ele" / "inside");  // a non-empty directory
  error_of([&] { expanse::write_ele_file(dir.path / "occupied.ele", two_triangles(), 0); },
           ErrorCode::io_error);
  CHECK(dir.entries() == 1);
  CHECK(fs::is_directory(dir.path / "occupied.ele"));
}

TEST_CASE("an existing output is replaced whole", "[io]") {
  TempDir dir;
  auto file = dir.write("p.node", "garbage that is longer than the new contents will be.......\n");
  expanse::write_node_file(file, std::vector<Point2>{{1, 2}}, 0);
  CHECK(expanse::read_node_file(file).points == std::vector<Point2>{{1, 2}});
  CHECK(dir.entries() == 1);
}

TEST_CASE("pictures are written as SVG and PNG", "[io][picture]") {
  TempDir dir;
  expanse::PictureOptions options;
  options.size = 200;
  options.triangle_origin = {0, 1};
  expanse::write_svg(dir.path / "m.svg", kSquare, two_triangles(), options);
  expanse::write_png(dir.path / "m.png", kSquare, two_triangles(), options);
  std::ifstream svg(dir.path / "m.svg");
  std::string text((std::istreambuf_iterator<char>(svg)), {});
  CHECK(text.find("<svg") != std::string::npos);
  CHECK(text.find("<polygon") != std::string::npos);  // the hull
  CHECK(text.find("</svg>") != std::string::npos);
  std::ifstream png(dir.path / "m.png", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(png)), {});
  REQUIRE(bytes.size() > 8);
  CHECK(bytes.substr(1, 3) == "PNG");
  CHECK(dir.entries() == 2);

  // Extreme magnitudes and a collinear hull (no triangles) still draw.
  expanse::Mesh line;
  line.hull = {0, 1};
  const std::vector<Point2> far = {{-1e300, 1e-300}, {1e300, 2e-300}};
  expanse::write_png(dir.path / "far.png", far, line, options = {});
  expanse::write_svg(dir.path / "far.svg", far, line, options);
  CHECK(fs::file_size(dir.path / "far.png") > 0);
}
