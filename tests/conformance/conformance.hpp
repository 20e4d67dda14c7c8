#pragma once
// Shared by every conformance test: which backend is under test, and the one comparison every
// case makes (CGAL's triangles, CGAL's hull, the checker, the representative map, the stats).
#include <span>
#include <string>
#include <string_view>

#include "expanse/mesh.hpp"
#include "expanse/options.hpp"
#include "expanse/types.hpp"

namespace expanse::conformance {

/// The backend named by --backend (set by main before any test runs).
BackendKind backend_under_test();

/// Options for the backend under test, with the given layout.
Options options(const Layout& layout = {});

/// Triangulates `points` with `opts` and CHECKs everything against CGAL. `label` names the
/// case in failure messages. When EXPANSE_SHRINK is set in the environment, a failing input is
/// shrunk to a small one that still fails and written to conformance-failures/ (for reports).
void expect_matches_cgal(std::string_view label, std::span<const Point2> points, const Options& opts);

/// What in `mesh`, made from `points` with `opts`, differs from CGAL (triangles, hull,
/// representatives, check_mesh, stats), as text; empty when nothing does.
std::string differences_from_cgal(std::span<const Point2> points, const Mesh& mesh, const Options& opts);

}  // namespace expanse::conformance
