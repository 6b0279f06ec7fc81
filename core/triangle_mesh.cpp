// Building a static triangle mesh (core/triangle_mesh.h): the triangles'
// planes, their active edges and the tree over them.
#include "core/triangle_mesh.h"

#include <algorithm>
#include <cstddef>
#include <string>
#include <tuple>

namespace bitstep {

namespace mesh_builder {

constexpr Fixed max_coordinate = Fixed::from_int(16000);

std::string vertex_place(size_t i, int axis) { return "vertices[" + std::to_string(i) + "]." + "xyz"[axis]; }

Result<void> check_arrays(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& indices) {
  if (vertices.size() > max_mesh_vertices) {
    return Error{"vertices",
                 std::to_string(vertices.size()) + " vertices, at most " + std::to_string(max_mesh_vertices)};
  }
  for (size_t i = 0; i < vertices.size(); ++i) {
    const Fixed c[3] = {vertices[i].x, vertices[i].y, vertices[i].z};
    for (int k = 0; k < 3; ++k) {
      if (c[k] < -max_coordinate || c[k] > max_coordinate) return Error{vertex_place(i, k), "outside -16000..16000 m"};
    }
  }
  if (indices.size() % 3 != 0) {
    return Error{"indices", std::to_string(indices.size()) + " indices, not a multiple of 3"};
  }
  const size_t triangles = indices.size() / 3;
  if (triangles == 0 || triangles > max_mesh_triangles) {
    return Error{"indices",
                 std::to_string(triangles) + " triangles: a mesh has 1 to " + std::to_string(max_mesh_triangles)};
  }
  for (size_t k = 0; k < indices.size(); ++k) {
    if (indices[k] >= vertices.size()) {
      return Error{"indices[" + std::to_string(k) + "]",
                   "vertex " + std::to_string(indices[k]) + " of " + std::to_string(vertices.size())};
    }
  }
  return {};
}

// The triangle's plane: the unit normal of (b - a) x (c - a), its offset.
Result<TriangleMesh::Triangle> make_triangle(const std::vector<Vec3>& v, uint32_t a, uint32_t b, uint32_t c,
                                             size_t index) {
  const Vec3 ab = v[b] - v[a], ac = v[c] - v[a], bc = v[c] - v[b];
  const auto too_long = [](Vec3 e) { return length(e) > mesh_max_edge; };  // length sums in 128 bits
  const std::string place = "triangle " + std::to_string(index);
  if (too_long(ab) || too_long(ac) || too_long(bc)) return Error{place, "an edge longer than 1000 m"};
  const Vec3 twice_area = cross(ab, ac);
  if (length(twice_area) < mesh_min_area + mesh_min_area) return Error{place, "area below 1e-6 m^2"};
  TriangleMesh::Triangle t;
  t.corners = {a, b, c};
  t.normal = normalize(twice_area);
  t.offset = dot(t.normal, v[a]);
  return t;
}

// Edge k of triangle t, as its two vertices (tail, head).
std::pair<uint32_t, uint32_t> edge_of(const TriangleMesh::Triangle& t, int k) {
  return {t.corners[static_cast<size_t>(k)], t.corners[static_cast<size_t>((k + 1) % 3)]};
}

// Active edges: sorted by their vertex pair, each edge's triangles are
// neighbours. Two triangles that run the edge opposite ways join there;
// the edge is inactive when the second's far corner lies on or above the
// first's plane (flat or bending inward) or their normals are within 5
// degrees. Any other edge (one triangle, three, or two that disagree on
// the winding) is active.
void mark_active_edges(TriangleMesh& mesh) {
  struct Use {
    uint32_t low, high, triangle;
    int edge;
  };
  std::vector<Use> uses;
  uses.reserve(mesh.triangles.size() * 3);
  for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto [tail, head] = edge_of(mesh.triangles[t], k);
      uses.push_back({std::min(tail, head), std::max(tail, head), t, k});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) {
    return std::tie(x.low, x.high, x.triangle, x.edge) < std::tie(y.low, y.high, y.triangle, y.edge);
  });
  for (size_t i = 0; i < uses.size();) {
    size_t j = i;
    while (j < uses.size() && uses[j].low == uses[i].low && uses[j].high == uses[i].high) ++j;
    bool active = true;
    if (j - i == 2) {
      TriangleMesh::Triangle& first = mesh.triangles[uses[i].triangle];
      TriangleMesh::Triangle& second = mesh.triangles[uses[i + 1].triangle];
      const bool opposite = edge_of(first, uses[i].edge).first == edge_of(second, uses[i + 1].edge).second;
      const Vec3 far = mesh.vertices[second.corners[static_cast<size_t>((uses[i + 1].edge + 2) % 3)]];
      const bool outward = dot(first.normal, far) < first.offset;
      active = !opposite || (outward && dot(first.normal, second.normal) < mesh_active_edge_cos);
    }
    for (size_t k = i; k < j; ++k) {
      if (active) mesh.triangles[uses[k].triangle].active_edges |= static_cast<uint8_t>(1u << uses[k].edge);
    }
    i = j;
  }
}

Aabb triangle_bounds(const TriangleMesh& mesh, uint32_t t) {
  const TriangleMesh::Triangle& tri = mesh.triangles[t];
  const Vec3 a = mesh.vertices[tri.corners[0]], b = mesh.vertices[tri.corners[1]], c = mesh.vertices[tri.corners[2]];
  return {min(min(a, b), c), max(max(a, b), c)};
}

// Three times the centre of triangle t along `axis`.
Fixed centre_3(const TriangleMesh& mesh, uint32_t t, int axis) {
  Fixed sum;
  for (const uint32_t corner : mesh.triangles[t].corners) {
    const Vec3 p = mesh.vertices[corner];
    sum += axis == 0 ? p.x : (axis == 1 ? p.y : p.z);
  }
  return sum;
}

// The node for order[lo, hi) at `index`; its children are appended.
void build_node(TriangleMesh& mesh, uint32_t index, uint32_t lo, uint32_t hi) {
  Aabb bounds = triangle_bounds(mesh, mesh.order[lo]);
  Vec3 centre_low{Fixed::max(), Fixed::max(), Fixed::max()}, centre_high = -centre_low;
  for (uint32_t k = lo; k < hi; ++k) {
    bounds = bounds.merged(triangle_bounds(mesh, mesh.order[k]));
    const Vec3 c{centre_3(mesh, mesh.order[k], 0), centre_3(mesh, mesh.order[k], 1), centre_3(mesh, mesh.order[k], 2)};
    centre_low = min(centre_low, c);
    centre_high = max(centre_high, c);
  }
  mesh.nodes[index].bounds = bounds;
  constexpr uint32_t leaf_size = 4;
  if (hi - lo <= leaf_size) {
    mesh.nodes[index].first = lo;
    mesh.nodes[index].count = hi - lo;
    return;
  }
  // Split at the median along the longest axis of the centres, ties by index.
  const Vec3 spread = centre_high - centre_low;
  const int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : (spread.y >= spread.z ? 1 : 2);
  const auto first = mesh.order.begin() + static_cast<std::ptrdiff_t>(lo);
  std::sort(first, first + static_cast<std::ptrdiff_t>(hi - lo), [&](uint32_t x, uint32_t y) {
    const Fixed cx = centre_3(mesh, x, axis), cy = centre_3(mesh, y, axis);
    return cx < cy || (cx == cy && x < y);
  });
  const uint32_t middle = lo + (hi - lo) / 2;
  const auto first_child = static_cast<uint32_t>(mesh.nodes.size());
  mesh.nodes.resize(mesh.nodes.size() + 2);
  mesh.nodes[index].first = first_child;
  mesh.nodes[index].count = 0;
  build_node(mesh, first_child, lo, middle);
  build_node(mesh, first_child + 1, middle, hi);
}

}  // namespace mesh_builder

Result<std::shared_ptr<const TriangleMesh>> build_triangle_mesh(const std::vector<Vec3>& vertices,
                                                                const std::vector<uint32_t>& indices,
                                                                std::shared_ptr<const HeightGrid> source_grid) {
  using namespace mesh_builder;
  if (Result<void> checked = check_arrays(vertices, indices); !checked.ok()) return checked.error();
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->vertices = vertices;
  for (size_t t = 0; t < indices.size() / 3; ++t) {
    auto triangle = make_triangle(vertices, indices[3 * t], indices[3 * t + 1], indices[3 * t + 2], t);
    if (!triangle.ok()) return triangle.error();
    mesh->triangles.push_back(triangle.value());
  }
  mark_active_edges(*mesh);
  mesh->order.resize(mesh->triangles.size());
  for (uint32_t t = 0; t < mesh->order.size(); ++t) mesh->order[t] = t;
  mesh->nodes.resize(1);
  build_node(*mesh, 0, 0, static_cast<uint32_t>(mesh->order.size()));
  mesh->bounds = mesh->nodes[0].bounds;
  for (const Vec3& v : mesh->vertices) mesh->extent = max(mesh->extent, length(v));
  mesh->source_grid = std::move(source_grid);
  return std::shared_ptr<const TriangleMesh>(std::move(mesh));
}

}  // namespace bitstep
