// The hull builder (core/convex_hull.h), in five steps:
//
//  1. Snap every coordinate to the 2^-20 m grid (raw Q32.32 >> 12, rounded
//     to nearest, ties to even) and drop repeated points (the first stays).
//  2. Triangulate the hull incrementally: a point goes in when it is strictly
//     outside some triangle's plane, replacing the triangles that see it by a
//     fan from their horizon. The one predicate is the sign of a triple
//     product of grid differences, exact in 128 bits, so a point exactly on a
//     plane is never outside it and no triangle has zero area.
//  3. Group the triangles of each exact plane into facets, then merge
//     neighbouring facets whose vertices all lie within
//     hull_coplanar_tolerance of the merged polygon's plane, the flattest
//     merge first, as long as the merged facet is one convex disk.
//  4. A facet's corners are its boundary's vertices less those in the middle
//     of a straight side. A point that is nobody's corner (inside a merged
//     facet, on an edge) goes, and steps 2-4 run again on the corners alone
//     until every point is a corner: building from a hull's own vertices then
//     repeats that last round exactly (build_convex_hull(hull.vertices) is
//     the same hull).
//  5. The output in a canonical order, and the mass properties of the exact
//     triangulated hull in exact big-integer sums, each rounded once.
#include "core/convex_hull.h"

#include <algorithm>
#include <array>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "fixed/big_int.h"
#include "fixed/vec3.h"

namespace bitstep {

// Named: the cross builds compile all of core/ as one translation unit,
// where an unnamed namespace's Edge or SignedBig would meet other files'.
namespace hull_builder {

// Raw Q32.32 -> grid units: a grid step is 2^12 raw.
constexpr int snap_shift = raw::fraction_bits - hull_grid_bits;
constexpr int64_t max_coordinate_raw = int64_t{50} << raw::fraction_bits;

// ---------------------------------------------------------------------------
// Grid points and the exact predicate.

// Integer coordinates in grid units: |c| <= 50 m = 50 2^20 < 2^26.
struct GridPoint {
  int64_t x = 0, y = 0, z = 0;
  friend constexpr bool operator==(GridPoint, GridPoint) = default;
};

using Points = std::vector<GridPoint>;
using Loop = std::vector<std::size_t>;

GridPoint operator-(GridPoint a, GridPoint b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
GridPoint operator+(GridPoint a, GridPoint b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
bool is_zero(GridPoint a) { return a.x == 0 && a.y == 0 && a.z == 0; }

// Of two differences of grid points (|component| < 2^27): each product is
// below 2^54 and each component below 2^55, exact in int64.
GridPoint cross(GridPoint a, GridPoint b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// v sign-extended to two's complement 128 bits.
Wide wide_of(int64_t v) { return v < 0 ? -Wide{magnitude(v)} : Wide{magnitude(v)}; }

// a . b exactly, in two's complement 128 bits. Every use has |a_i b_i| below
// 2^120 (a normal of at most 2^62 against a difference or a cross product),
// so the sum never wraps.
Wide wide_dot(GridPoint a, GridPoint b) {
  return raw::signed_product<Wide>(a.x, b.x) + raw::signed_product<Wide>(a.y, b.y) +
         raw::signed_product<Wide>(a.z, b.z);
}

int sign_of(Wide w) {
  if (w == Wide{0}) return 0;
  return top_bit(w) ? -1 : 1;
}

// A two's complement 128-bit value as int64, when it is inside +-2^62.
std::optional<int64_t> narrow(Wide w) {
  const bool negative = top_bit(w);
  const Wide m = negative ? -w : w;
  if (m.hi() != 0 || m.lo() >= (uint64_t{1} << 62)) return std::nullopt;
  const auto value = static_cast<int64_t>(m.lo());
  return negative ? -value : value;
}

// round(raw / 2^12), ties to even: >> is a floor in C++20.
int64_t snap(Fixed coordinate) {
  const int64_t r = coordinate.raw();
  int64_t q = r >> snap_shift;
  const int64_t rest = r - q * (int64_t{1} << snap_shift);  // 0 .. 2^12 - 1
  constexpr int64_t half = int64_t{1} << (snap_shift - 1);
  if (rest > half || (rest == half && (q & 1) != 0)) ++q;
  return q;
}

Fixed from_grid(int64_t q) { return Fixed::from_raw(q * (int64_t{1} << snap_shift)); }
Vec3 from_grid(GridPoint p) { return {from_grid(p.x), from_grid(p.y), from_grid(p.z)}; }
// An integer vector as raw values: only its direction is used (normalize).
Vec3 as_raw(GridPoint n) { return {Fixed::from_raw(n.x), Fixed::from_raw(n.y), Fixed::from_raw(n.z)}; }

// ---------------------------------------------------------------------------
// Step 2: the triangulated hull.

struct Triangle {
  std::array<std::size_t, 3> v{};  // counter-clockwise seen from outside
  GridPoint normal;                // (v1 - v0) x (v2 - v0): outward
};

Triangle make_triangle(const Points& p, std::size_t a, std::size_t b, std::size_t c) {
  return {{a, b, c}, cross(p[b] - p[a], p[c] - p[a])};
}

// 1: q strictly outside the triangle's plane; 0: on it; -1: inside.
int side(const Points& p, const Triangle& t, GridPoint q) { return sign_of(wide_dot(t.normal, q - p[t.v[0]])); }

// Four points spanning a volume, the first ones found in input order, or
// nothing when all the points lie in one plane.
std::optional<std::array<std::size_t, 4>> first_simplex(const Points& p) {
  if (p.size() < 4) return std::nullopt;
  std::size_t c = 2;
  while (c < p.size() && is_zero(cross(p[1] - p[0], p[c] - p[0]))) ++c;
  if (c == p.size()) return std::nullopt;
  const Triangle base = make_triangle(p, 0, 1, c);
  std::size_t d = c + 1;  // the points before c are on the line through p[0], p[1]
  while (d < p.size() && side(p, base, p[d]) == 0) ++d;
  if (d == p.size()) return std::nullopt;
  return std::array<std::size_t, 4>{0, 1, c, d};
}

// The tetrahedron's faces, each turned so that the fourth point is inside.
std::vector<Triangle> tetrahedron(const Points& p, std::array<std::size_t, 4> s) {
  if (side(p, make_triangle(p, s[0], s[1], s[2]), p[s[3]]) > 0) std::swap(s[1], s[2]);
  return {make_triangle(p, s[0], s[1], s[2]), make_triangle(p, s[0], s[3], s[1]), make_triangle(p, s[1], s[3], s[2]),
          make_triangle(p, s[2], s[3], s[0])};
}

// Point q into the hull: the triangles that see it (q strictly outside their
// plane) give way to a fan from q over their horizon, the edges they share
// with the rest. Each horizon edge keeps its direction, so the new triangles
// stay counter-clockwise seen from outside.
void add_point(const Points& p, std::vector<Triangle>& triangles, std::size_t q) {
  std::vector<bool> sees(triangles.size());
  std::set<std::pair<std::size_t, std::size_t>> seen_edges;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    if (side(p, triangles[i], p[q]) <= 0) continue;
    sees[i] = true;
    const auto& v = triangles[i].v;
    for (std::size_t k = 0; k < 3; ++k) seen_edges.insert({v[k], v[(k + 1) % 3]});
  }
  if (seen_edges.empty()) return;
  std::vector<Triangle> next;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    if (!sees[i]) next.push_back(triangles[i]);
  }
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    if (!sees[i]) continue;
    const auto& v = triangles[i].v;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t a = v[k], b = v[(k + 1) % 3];
      if (seen_edges.count({b, a}) == 0) next.push_back(make_triangle(p, a, b, q));
    }
  }
  triangles = std::move(next);
}

std::optional<std::vector<Triangle>> triangulate(const Points& p) {
  const auto simplex = first_simplex(p);
  if (!simplex) return std::nullopt;
  std::vector<Triangle> triangles = tetrahedron(p, *simplex);
  for (std::size_t q = 0; q < p.size(); ++q) {
    if (std::find(simplex->begin(), simplex->end(), q) == simplex->end()) add_point(p, triangles, q);
  }
  return triangles;
}

// ---------------------------------------------------------------------------
// Step 3: facets.

using Edge = std::pair<std::size_t, std::size_t>;  // (tail, head)

struct Surface {
  const Points& points;
  std::vector<Triangle> triangles;
  std::map<Edge, std::size_t> owner;  // directed edge -> the triangle that has it
};

Surface make_surface(const Points& p, std::vector<Triangle> triangles) {
  Surface s{p, std::move(triangles), {}};
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const auto& v = s.triangles[i].v;
    for (std::size_t k = 0; k < 3; ++k) s.owner[{v[k], v[(k + 1) % 3]}] = i;
  }
  return s;
}

std::size_t across(const Surface& s, Edge e) { return s.owner.at({e.second, e.first}); }

struct Facet {
  std::vector<std::size_t> triangles;  // ascending
  Loop loop;                           // its boundary, counter-clockwise seen from outside
  GridPoint normal;                    // Newell's: twice the loop's vector area
  Fixed width;                         // the spread of its triangles' vertices along the normal
};

// The boundary of a set of triangles as one simple cycle (the edges whose
// reverse is not in the set), from its lowest vertex; nothing when the set is
// not a disk.
std::optional<Loop> boundary(const Surface& s, const std::vector<std::size_t>& triangles) {
  std::set<Edge> edges;
  for (const std::size_t t : triangles) {
    const auto& v = s.triangles[t].v;
    for (std::size_t k = 0; k < 3; ++k) edges.insert({v[k], v[(k + 1) % 3]});
  }
  std::map<std::size_t, std::size_t> next;
  for (const auto& [tail, head] : edges) {
    if (edges.count({head, tail}) == 0 && !next.emplace(tail, head).second) return std::nullopt;  // pinched
  }
  if (next.empty()) return std::nullopt;
  Loop loop;
  std::size_t v = next.begin()->first;
  do {
    loop.push_back(v);
    const auto it = next.find(v);
    if (it == next.end() || loop.size() > next.size()) return std::nullopt;
    v = it->second;
  } while (v != loop.front());
  if (loop.size() != next.size()) return std::nullopt;  // a second cycle: a ring, not a disk
  return loop;
}

// Newell's normal: sum of (v_i - v_0) x (v_i+1 - v_0), twice the vector area,
// summed in 128 bits; nothing if it does not fit in 2^62 (a loop no hull has).
std::optional<GridPoint> loop_normal(const Points& p, const Loop& loop) {
  Wide sum[3] = {};
  for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
    const GridPoint c = cross(p[loop[i]] - p[loop[0]], p[loop[i + 1]] - p[loop[0]]);
    sum[0] = sum[0] + wide_of(c.x);
    sum[1] = sum[1] + wide_of(c.y);
    sum[2] = sum[2] + wide_of(c.z);
  }
  const auto x = narrow(sum[0]), y = narrow(sum[1]), z = narrow(sum[2]);
  if (!x || !y || !z) return std::nullopt;
  return GridPoint{*x, *y, *z};
}

// Whether b is in the middle of a straight side a -> b -> c.
bool is_straight(const Points& p, std::size_t a, std::size_t b, std::size_t c) {
  return is_zero(cross(p[b] - p[a], p[c] - p[b]));
}

// The first vertex of the loop where it does not turn left about `normal`
// nor go straight on: none when the loop is a convex polygon seen from the
// normal's side.
std::optional<std::size_t> reflex_corner(const Points& p, const Loop& loop, GridPoint normal) {
  const std::size_t n = loop.size();
  for (std::size_t i = 0; i < n; ++i) {
    const GridPoint in = p[loop[i]] - p[loop[(i + n - 1) % n]], out = p[loop[(i + 1) % n]] - p[loop[i]];
    const GridPoint turn = cross(in, out);
    const int along = is_zero(turn) ? sign_of(wide_dot(in, out)) : sign_of(wide_dot(turn, normal));
    if (along <= 0) return loop[i];
  }
  return std::nullopt;
}

// max - min of dot(n, v) over the triangles' vertices, n the unit normal.
Fixed spread(const Surface& s, const std::vector<std::size_t>& triangles, GridPoint normal) {
  const Vec3 n = normalize(as_raw(normal));
  Fixed lo = Fixed::max(), hi = Fixed::lowest();
  for (const std::size_t t : triangles) {
    for (const std::size_t v : s.triangles[t].v) {
      const Fixed d = dot(n, from_grid(s.points[v]));
      lo = min(lo, d);
      hi = max(hi, d);
    }
  }
  return hi - lo;
}

// The facet of a set of triangles, if it is a disk (convex or not).
std::optional<Facet> make_facet(const Surface& s, std::vector<std::size_t> triangles) {
  std::sort(triangles.begin(), triangles.end());
  auto loop = boundary(s, triangles);
  if (!loop) return std::nullopt;
  const auto normal = loop_normal(s.points, *loop);
  if (!normal || is_zero(*normal)) return std::nullopt;
  const Fixed width = spread(s, triangles, *normal);
  return Facet{std::move(triangles), std::move(*loop), *normal, width};
}

// The triangles grouped by exact plane: neighbours whose planes are one (the
// far vertex of one on the plane of the other), joined by union-find rooted
// at the lowest index.
std::vector<std::vector<std::size_t>> exact_planes(const Surface& s) {
  std::vector<std::size_t> root(s.triangles.size());
  for (std::size_t i = 0; i < root.size(); ++i) root[i] = i;
  auto find = [&](std::size_t i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const auto& v = s.triangles[i].v;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t j = across(s, {v[k], v[(k + 1) % 3]});
      const auto& w = s.triangles[j].v;
      const std::size_t far = w[0] + w[1] + w[2] - v[k] - v[(k + 1) % 3];
      if (side(s.points, s.triangles[i], s.points[far]) != 0) continue;
      const std::size_t a = find(i), b = find(j);
      root[std::max(a, b)] = std::min(a, b);
    }
  }
  std::map<std::size_t, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < root.size(); ++i) groups[find(i)].push_back(i);
  std::vector<std::vector<std::size_t>> planes;
  for (auto& [r, triangles] : groups) planes.push_back(std::move(triangles));
  return planes;
}

// Facets that merge within the tolerance, in two passes:
//  - whole flat regions: the facets joined by pairs that merge within the
//    tolerance, merged at once when all of them make one convex disk within
//    it (a face of many points a hair off its plane);
//  - then the flattest group first (ties by facet index) until no group
//    merges. The groups tried are the pairs of neighbours, each grown until
//    its polygon is convex: a reflex corner takes in every facet around it,
//    so that it ends inside (a vertex raised a hair above a face's middle is
//    a reflex corner of any two of its triangles, the middle of all of
//    them), while the group stays a disk within the tolerance of at most
//    max_grown_triangles triangles (which bounds the work on a large,
//    slightly curved surface).
// Dead facets keep their slot, emptied.
class FacetMerger {
 public:
  FacetMerger(const Surface& s, std::vector<Facet> facets)
      : s_(s), facets_(std::move(facets)), facet_of_(s.triangles.size(), 0) {
    for (std::size_t f = 0; f < facets_.size(); ++f) {
      for (const std::size_t t : facets_[f].triangles) facet_of_[t] = f;
    }
  }

  std::vector<Facet> run() {
    merge_flat_regions();
    while (merge_flattest()) {
    }
    std::vector<Facet> alive;
    for (Facet& f : facets_) {
      if (!f.triangles.empty()) alive.push_back(std::move(f));
    }
    return alive;
  }

 private:
  static constexpr std::size_t max_grown_triangles = 32;
  using Group = std::set<std::size_t>;  // facet indices
  struct Merge {
    Group touched;               // the pair and what it took in, merged or not
    std::optional<Facet> facet;  // set when the group merges
  };

  // The facets around each loop vertex, and the pairs of neighbours.
  std::set<std::pair<std::size_t, std::size_t>> survey() {
    star_.clear();
    std::set<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t f = 0; f < facets_.size(); ++f) {
      const Loop& loop = facets_[f].loop;
      for (std::size_t i = 0; i < loop.size(); ++i) {
        star_[loop[i]].insert(f);
        const std::size_t g = facet_of_[across(s_, {loop[i], loop[(i + 1) % loop.size()]})];
        pairs.insert({std::min(f, g), std::max(f, g)});
      }
    }
    return pairs;
  }

  // The facet of the group's triangles, if it is a disk within the tolerance.
  std::optional<Facet> flat_union(const Group& members) const {
    std::vector<std::size_t> triangles;
    for (const std::size_t f : members) {
      triangles.insert(triangles.end(), facets_[f].triangles.begin(), facets_[f].triangles.end());
    }
    std::optional<Facet> facet = make_facet(s_, std::move(triangles));
    if (facet && facet->width > hull_coplanar_tolerance) facet.reset();
    return facet;
  }

  void merge(const Group& members, Facet facet) {
    const std::size_t into = *members.begin();
    for (const std::size_t f : members) facets_[f] = Facet{};
    facets_[into] = std::move(facet);
    for (const std::size_t t : facets_[into].triangles) facet_of_[t] = into;
  }

  void merge_flat_regions() {
    std::vector<std::size_t> root(facets_.size());
    for (std::size_t i = 0; i < root.size(); ++i) root[i] = i;
    auto find = [&](std::size_t i) {
      while (root[i] != i) i = root[i] = root[root[i]];
      return i;
    };
    for (const auto& [f, g] : survey()) {
      if (flat_union({f, g})) {
        const std::size_t a = find(f), b = find(g);
        root[std::max(a, b)] = std::min(a, b);
      }
    }
    std::map<std::size_t, Group> regions;
    for (std::size_t f = 0; f < facets_.size(); ++f) regions[find(f)].insert(f);
    for (const auto& [r, members] : regions) {
      if (members.size() < 2) continue;
      std::optional<Facet> facet = flat_union(members);
      if (facet && !reflex_corner(s_.points, facet->loop, facet->normal)) merge(members, std::move(*facet));
    }
  }

  // The group grown from a pair to a convex disk within the tolerance.
  Merge grow(Group members) const {
    for (;;) {
      std::size_t count = 0;
      for (const std::size_t f : members) count += facets_[f].triangles.size();
      std::optional<Facet> facet = count <= max_grown_triangles ? flat_union(members) : std::nullopt;
      if (!facet) return {std::move(members), std::nullopt};
      const auto reflex = reflex_corner(s_.points, facet->loop, facet->normal);
      if (!reflex) return {std::move(members), std::move(facet)};
      const std::size_t before = members.size();
      members.insert(star_.at(*reflex).begin(), star_.at(*reflex).end());
      if (members.size() == before) return {std::move(members), std::nullopt};
    }
  }

  const Merge& merged(std::pair<std::size_t, std::size_t> pair) {
    const auto it = cache_.find(pair);
    if (it != cache_.end()) return it->second;
    return cache_.emplace(pair, grow({pair.first, pair.second})).first->second;
  }

  bool merge_flattest() {
    const Merge* best = nullptr;
    for (const auto& pair : survey()) {
      const Merge& m = merged(pair);
      if (m.facet && (best == nullptr || m.facet->width < best->facet->width)) best = &m;
    }
    if (best == nullptr) return false;
    const Group members = best->touched;
    merge(members, *best->facet);
    // A cached group that took in any of the merged facets is stale.
    std::erase_if(cache_, [&](const auto& entry) {
      const Group& touched = entry.second.touched;
      return std::any_of(touched.begin(), touched.end(), [&](std::size_t f) { return members.count(f) != 0; });
    });
    return true;
  }

  const Surface& s_;
  std::vector<Facet> facets_;
  std::vector<std::size_t> facet_of_;                  // triangle -> facet
  std::map<std::size_t, std::set<std::size_t>> star_;  // loop vertex -> its facets
  std::map<std::pair<std::size_t, std::size_t>, Merge> cache_;
};

// ---------------------------------------------------------------------------
// Step 4: corners.

struct Topology {
  std::vector<Loop> loops;           // the faces' corners, point indices, counter-clockwise
  std::vector<std::size_t> corners;  // ascending
  std::vector<Triangle> triangles;   // the exact hull
};

// The loop less the vertices in the middle of a straight side.
Loop without_straight(const Points& p, Loop loop) {
  for (std::size_t i = 0; i < loop.size() && loop.size() > 3;) {
    const std::size_t n = loop.size();
    if (is_straight(p, loop[(i + n - 1) % n], loop[i], loop[(i + 1) % n])) {
      loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
      i = 0;
    } else {
      ++i;
    }
  }
  return loop;
}

Error flat_error(Fixed thickness);

Result<Topology> hull_topology(const Points& p) {
  auto triangles = triangulate(p);
  if (!triangles) return flat_error(Fixed{});
  const Surface s = make_surface(p, std::move(*triangles));
  std::vector<Facet> facets;
  for (auto& plane : exact_planes(s)) {
    auto facet = make_facet(s, std::move(plane));
    if (!facet || reflex_corner(p, facet->loop, facet->normal)) {
      return Error{"", "internal: an exact facet is not a convex disk"};
    }
    facets.push_back(std::move(*facet));
  }
  Topology topology;
  std::set<std::size_t> corners;
  for (Facet& f : FacetMerger(s, std::move(facets)).run()) {
    Loop loop = without_straight(p, std::move(f.loop));
    if (loop.size() < 3) return flat_error(Fixed{});
    corners.insert(loop.begin(), loop.end());
    topology.loops.push_back(std::move(loop));
  }
  topology.corners.assign(corners.begin(), corners.end());
  topology.triangles = s.triangles;
  return topology;
}

// Steps 2-4 until every point is a corner.
Result<Topology> stable_topology(Points& points) {
  for (;;) {
    auto topology = hull_topology(points);
    if (!topology.ok() || topology->corners.size() == points.size()) return topology;
    Points corners;
    for (const std::size_t c : topology->corners) corners.push_back(points[c]);
    points = std::move(corners);
  }
}

// ---------------------------------------------------------------------------
// Refusals.

// x m as text to 0.0001 m, trailing zeros dropped ("0.004", "0.02"); rounded
// to nearest, or down when `down` (a thickness below the limit never prints
// as the limit). 0 <= x <= 200 m keeps x 10^4 in int64.
std::string metres(Fixed x, bool down) {
  const int64_t rounding = down ? 0 : int64_t{1} << (raw::fraction_bits - 1);
  const int64_t units = (x.raw() * 10000 + rounding) >> raw::fraction_bits;
  std::string fraction = std::to_string(10000 + units % 10000).substr(1);
  while (!fraction.empty() && fraction.back() == '0') fraction.pop_back();
  return std::to_string(units / 10000) + (fraction.empty() ? "" : "." + fraction);
}

Error flat_error(Fixed thickness) {
  const std::string limit = metres(hull_min_width, false);
  std::string thick = metres(thickness, false);
  if (thick == limit) thick = metres(thickness, true);
  return {"", "flat: " + thick + " m thick, at least " + limit + " m"};
}

std::optional<Error> check_points(const std::vector<Vec3>& points) {
  const auto n = points.size();
  if (n < 4 || n > static_cast<std::size_t>(max_hull_points)) {
    return Error{"", std::to_string(n) + " points: a hull needs 4 to " + std::to_string(max_hull_points)};
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Fixed c[3] = {points[i].x, points[i].y, points[i].z};
    for (std::size_t k = 0; k < 3; ++k) {
      if (c[k].raw() > max_coordinate_raw || c[k].raw() < -max_coordinate_raw) {
        return Error{"points[" + std::to_string(i) + "]." + "xyz"[k], "outside -50..50 m"};
      }
    }
  }
  return std::nullopt;
}

Points snapped_distinct(const std::vector<Vec3>& points) {
  Points result;
  for (const Vec3& v : points) {
    const GridPoint g{snap(v.x), snap(v.y), snap(v.z)};
    if (std::find(result.begin(), result.end(), g) == result.end()) result.push_back(g);
  }
  return result;
}

// ---------------------------------------------------------------------------
// Step 5: the output.

// a before b in lexicographic order, written out: GCC 12's libstdc++
// compares vectors of wider-than-byte unsigned integers with a memcmp of
// as many bytes as elements on big-endian targets (s390x saw [21, 22, 23]
// equal to [3, 4, 5]), so `loops[i] < loops[j]` would order faces by
// byte order.
bool lexicographically_before(const Loop& a, const Loop& b) {
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (a[i] != b[i]) return a[i] < b[i];
  }
  return a.size() < b.size();
}

// Each loop from its lowest index, the loops in lexicographic order.
std::vector<Loop> canonical_loops(std::vector<Loop> loops) {
  for (Loop& loop : loops) std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
  std::sort(loops.begin(), loops.end(), lexicographically_before);
  return loops;
}

void add_faces(ConvexHull& hull, const Points& p, const std::vector<Loop>& loops) {
  for (const Loop& loop : loops) {
    ConvexHull::Face face;
    face.normal = normalize(as_raw(*loop_normal(p, loop)));
    face.offset = Fixed::lowest();
    for (const Vec3& v : hull.vertices) face.offset = max(face.offset, dot(face.normal, v));
    face.first = static_cast<uint16_t>(hull.face_vertices.size());
    face.count = static_cast<uint16_t>(loop.size());
    for (const std::size_t v : loop) hull.face_vertices.push_back(static_cast<uint16_t>(v));
    hull.faces.push_back(face);
  }
}

// Each edge once, tail < head, `face` the one with tail -> head; sorted.
bool add_edges(ConvexHull& hull, const std::vector<Loop>& loops) {
  std::map<Edge, std::size_t> face_of;
  for (std::size_t f = 0; f < loops.size(); ++f) {
    for (std::size_t i = 0; i < loops[f].size(); ++i) {
      if (!face_of.emplace(Edge{loops[f][i], loops[f][(i + 1) % loops[f].size()]}, f).second) return false;
    }
  }
  for (const auto& [edge, f] : face_of) {
    const auto twin = face_of.find({edge.second, edge.first});
    if (twin == face_of.end()) return false;
    if (edge.first > edge.second) continue;
    hull.edges.push_back({static_cast<uint16_t>(edge.first), static_cast<uint16_t>(edge.second),
                          static_cast<uint16_t>(f), static_cast<uint16_t>(twin->second)});
  }
  for (const ConvexHull::Edge& e : hull.edges) {
    hull.edge_directions.push_back(normalize(hull.vertices[e.head] - hull.vertices[e.tail]));
  }
  return true;  // std::map iterates (tail, head) in order
}

// The least, over faces, of the farthest vertex's depth behind the face.
Fixed thickness(const ConvexHull& hull) {
  Fixed thinnest = Fixed::max();
  for (const ConvexHull::Face& face : hull.faces) {
    Fixed deepest{};
    for (const Vec3& v : hull.vertices) deepest = max(deepest, face.offset - dot(face.normal, v));
    thinnest = min(thinnest, deepest);
  }
  return thinnest;
}

// ---------------------------------------------------------------------------
// Mass properties: exact sums over the tetrahedra from a hull vertex r to
// each triangle, in signed big integers, each output rounded once.

using Big = BigUint<8>;

using SignedBig = BigInt<8>;

SignedBig big_of(int64_t v) { return SignedBig::from_i64(v); }
SignedBig big_of(Wide v) {  // two's complement 128 bits
  const bool negative = top_bit(v);
  const Wide m = negative ? -v : v;
  Big b = Big::from_u64(m.hi());
  b.shift_left(64);
  b.add(Big::from_u64(m.lo()));
  return {b, negative};
}

SignedBig shifted(SignedBig a, int bits) {
  a.magnitude.shift_left(bits);
  return a;
}

// round(numerator / denominator) as raw Q32.32, ties to even. The callers'
// bounds keep the quotient below 2^62 and every value below 2^256.
Fixed divide(const SignedBig& numerator, const Big& denominator) {
  Big remainder;
  uint64_t q = divide_small_quotient(numerator.magnitude, denominator, 63, remainder);
  remainder.shift_left(1);
  const int half = remainder.compare(denominator);
  if (half > 0 || (half == 0 && (q & 1u) != 0)) ++q;
  const auto value = static_cast<int64_t>(q);
  return Fixed::from_raw(numerator.negative ? -value : value);
}

// For each tetrahedron (r, a, b, c), with a, b, c relative to r (grid units,
// below 2^27) and D its determinant (6 its volume, >= 0 since r is on the
// hull): the sums
//   D6  = sum D                                  (6 V)
//   S1  = sum D (a + b + c)                      (24 V c, c the centroid)
//   S2  = sum D (a a^T + b b^T + c c^T + s s^T)  (120 integral of x x^T), s = a + b + c
// (Tonon 2004: the second moment of a tetrahedron with a vertex at the origin).
struct Moments {
  SignedBig d6;
  SignedBig s1[3];
  SignedBig s2[3][3];
};

Moments moments(const Points& p, const std::vector<Triangle>& triangles, GridPoint r) {
  Moments m;
  for (const Triangle& t : triangles) {
    const GridPoint a = p[t.v[0]] - r, b = p[t.v[1]] - r, c = p[t.v[2]] - r;
    const SignedBig d = big_of(wide_dot(a, cross(b, c)));
    const GridPoint s = a + b + c;  // below 2^29
    const int64_t sa[3] = {s.x, s.y, s.z}, aa[3] = {a.x, a.y, a.z}, ba[3] = {b.x, b.y, b.z}, ca[3] = {c.x, c.y, c.z};
    m.d6 = m.d6 + d;
    for (std::size_t i = 0; i < 3; ++i) {
      m.s1[i] = m.s1[i] + d * big_of(sa[i]);
      for (std::size_t j = i; j < 3; ++j) {
        // Each product below 2^58, the sum below 2^60: exact in int64.
        const int64_t second = aa[i] * aa[j] + ba[i] * ba[j] + ca[i] * ca[j] + sa[i] * sa[j];
        m.s2[i][j] = m.s2[i][j] + d * big_of(second);
      }
    }
  }
  return m;
}

// From the sums, in grid units g = 2^-20 m and raw units 2^-32:
//   V = D6 / 6 g^3                      raw: D6 2^32 / (6 2^60)
//   centroid = r + S1 / (4 D6) g        raw: r 2^12 + S1 2^10 / D6
//   J = integral (x - c)(x - c)^T / V = S2 / (20 D6) - S1 S1^T / (16 D6^2)
//     = (4 D6 S2 - 5 S1 S1^T) / (80 D6^2) g^2,  raw: that / 2^8
//   unit inertia = trace(J) 1 - J (I_xy = -integral x y dm).
// Bounds (100 m span): D6 < 2^83, S1 < 2^111, S2 < 2^140, the numerators of
// J below 2^226 and its denominator below 2^180.
void add_mass(ConvexHull& hull, const Points& p, const std::vector<Triangle>& triangles) {
  const GridPoint r = p[0];
  const Moments m = moments(p, triangles, r);
  hull.volume = divide(m.d6, Big::from_u64(uint64_t{6} << 28));
  const int64_t ra[3] = {r.x, r.y, r.z};
  Fixed centroid[3];
  for (std::size_t i = 0; i < 3; ++i) centroid[i] = from_grid(ra[i]) + divide(shifted(m.s1[i], 10), m.d6.magnitude);
  hull.centroid = {centroid[0], centroid[1], centroid[2]};

  SignedBig j[3][3];  // 80 D6^2 2^8 J in raw units
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t b = a; b < 3; ++b) {
      j[a][b] = j[b][a] = big_of(int64_t{4}) * m.d6 * m.s2[a][b] - big_of(int64_t{5}) * m.s1[a] * m.s1[b];
    }
  }
  const Big denominator = (big_of(int64_t{80 << 8}) * m.d6 * m.d6).magnitude;
  Fixed inertia[3][3];
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t b = 0; b < 3; ++b) {
      const std::size_t u = (a + 1) % 3, w = (a + 2) % 3;
      inertia[a][b] = a == b ? divide(j[u][u] + j[w][w], denominator) : divide(-j[a][b], denominator);
    }
  }
  for (std::size_t a = 0; a < 3; ++a) hull.unit_inertia.rows[a] = {inertia[a][0], inertia[a][1], inertia[a][2]};
}

}  // namespace hull_builder

Result<std::shared_ptr<const ConvexHull>> build_convex_hull(const std::vector<Vec3>& points) {
  using namespace hull_builder;
  if (auto error = check_points(points)) return *error;
  Points p = snapped_distinct(points);
  auto topology = stable_topology(p);
  if (!topology.ok()) return topology.error();
  if (p.size() > static_cast<std::size_t>(max_hull_vertices)) {
    return Error{"", std::to_string(p.size()) + " corners, at most " + std::to_string(max_hull_vertices)};
  }
  auto hull = std::make_shared<ConvexHull>();
  for (const GridPoint& g : p) hull->vertices.push_back(from_grid(g));
  const std::vector<Loop> loops = canonical_loops(std::move(topology->loops));
  add_faces(*hull, p, loops);
  if (!add_edges(*hull, loops)) return Error{"", "internal: the hull's faces do not close"};
  const Fixed thinnest = thickness(*hull);
  if (thinnest < hull_min_width) return flat_error(thinnest);
  add_mass(*hull, p, topology->triangles);
  hull->extent = Fixed{};
  for (const Vec3& v : hull->vertices) hull->extent = max(hull->extent, length(v));
  return std::shared_ptr<const ConvexHull>(std::move(hull));
}

}  // namespace bitstep
