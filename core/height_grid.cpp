// Building a heightfield's mesh from its grid (core/height_grid.h).
#include "core/height_grid.h"

#include <string>
#include <tuple>
#include <utility>

namespace bitstep {

namespace height_grid_builder {

Result<void> check_grid(const HeightGrid& g) {
  for (const auto& [name, count] : {std::pair{"columns", g.columns}, std::pair{"rows", g.rows}}) {
    if (count < 2 || count > max_grid_samples) {
      return Error{name, std::to_string(count) + ", a grid has 2 to " + std::to_string(max_grid_samples)};
    }
  }
  if (uint64_t{g.columns - 1} * (g.rows - 1) > max_grid_cells) {
    return Error{"rows", std::to_string(uint64_t{g.columns - 1} * (g.rows - 1)) + " cells, at most " +
                             std::to_string(max_grid_cells)};
  }
  for (const auto& [name, spacing, samples] :
       {std::tuple{"spacing_x", g.spacing_x, g.columns}, std::tuple{"spacing_z", g.spacing_z, g.rows}}) {
    if (spacing < min_grid_spacing || spacing > max_grid_spacing) return Error{name, "outside 0.01..1000 m"};
    // (samples - 1) spacing <= 16000 m, compared without forming the product.
    if (spacing > max_grid_span / Fixed::from_int(static_cast<int32_t>(samples - 1))) {
      return Error{name, "the grid spans more than 16000 m"};
    }
  }
  if (g.heights.size() != size_t{g.columns} * g.rows) {
    return Error{"heights", std::to_string(g.heights.size()) + " heights, not " + std::to_string(g.columns) + " x " +
                                std::to_string(g.rows)};
  }
  for (size_t k = 0; k < g.heights.size(); ++k) {
    if (g.heights[k] < -max_grid_span || g.heights[k] > max_grid_span) {
      return Error{"heights[" + std::to_string(k) + "]", "outside -16000..16000 m"};
    }
  }
  for (size_t k = 0; k < g.holes.size(); ++k) {
    const std::string place = "holes[" + std::to_string(k) + "]";
    if (g.holes[k] >= g.cell_count()) {
      return Error{place, "cell " + std::to_string(g.holes[k]) + " of " + std::to_string(g.cell_count())};
    }
    if (k > 0 && g.holes[k] <= g.holes[k - 1]) return Error{place, "holes not ascending, or one listed twice"};
  }
  if (g.holes.size() == g.cell_count()) return Error{"holes", "every cell a hole: no ground"};
  return {};
}

}  // namespace height_grid_builder

Result<std::shared_ptr<const TriangleMesh>> build_height_grid_mesh(HeightGrid grid) {
  if (Result<void> checked = height_grid_builder::check_grid(grid); !checked.ok()) return checked.error();
  std::vector<Vec3> vertices;
  vertices.reserve(grid.heights.size());
  for (uint32_t j = 0; j < grid.rows; ++j) {
    for (uint32_t i = 0; i < grid.columns; ++i) {
      vertices.push_back({grid.spacing_x * Fixed::from_int(static_cast<int32_t>(i)),
                          grid.heights[size_t{j} * grid.columns + i],
                          grid.spacing_z * Fixed::from_int(static_cast<int32_t>(j))});
    }
  }
  // Cell (i, j): corners s00 = (i, j), s10 = (i + 1, j), s01 = (i, j + 1),
  // s11 = (i + 1, j + 1); triangles (s00, s01, s11) and (s00, s11, s10),
  // counter-clockwise seen from +y: (s01 - s00) x (s11 - s00) = (0, dx dz, 0)
  // on flat ground.
  std::vector<uint32_t> indices;
  indices.reserve(size_t{6} * (grid.cell_count() - grid.holes.size()));
  size_t next_hole = 0;
  for (uint32_t j = 0; j + 1 < grid.rows; ++j) {
    for (uint32_t i = 0; i + 1 < grid.columns; ++i) {
      const uint32_t cell = j * (grid.columns - 1) + i;
      if (next_hole < grid.holes.size() && grid.holes[next_hole] == cell) {
        ++next_hole;
        continue;
      }
      const uint32_t s00 = j * grid.columns + i, s10 = s00 + 1, s01 = s00 + grid.columns, s11 = s01 + 1;
      indices.insert(indices.end(), {s00, s01, s11, s00, s11, s10});
    }
  }
  auto source = std::make_shared<const HeightGrid>(std::move(grid));
  Result<std::shared_ptr<const TriangleMesh>> mesh = build_triangle_mesh(vertices, indices, source);
  if (!mesh.ok()) return Error{"heights", mesh.error().place + ": " + mesh.error().reason};
  return mesh;
}

}  // namespace bitstep
