// Heightfields: a grid of heights, the usual way to give a level its
// terrain. A heightfield is a static triangle mesh (core/triangle_mesh.h)
// built from the grid, so it collides, casts and overlaps exactly as a
// mesh does (active edges included: a body sliding across it meets no
// bump at a cell's border or diagonal); only its source and its size in a
// state image differ (the grid is stored, not the triangles).
//
// The grid in the shape's frame: sample (i, j), column i along x and row j
// along z, lies at (i spacing_x, heights[j columns + i], j spacing_z), so
// the shape's origin is the first sample's foot and the grid spreads
// toward +x and +z. Each cell (i, j) between samples (i, j) and
// (i + 1, j + 1) is two triangles split along that diagonal, their fronts
// up (+y); a hole is a cell without them.
//
// Limits (each refused with a one-line reason naming the field): 2 to
// 4097 columns and rows, at most 2^19 cells (2^20 triangles), a spacing of
// 0.01 to 1000 m, a span within 16,000 m along x and along z, heights
// within 16,000 m, holes each a cell of the grid, listed once, ascending,
// and not every cell.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/error.h"
#include "core/triangle_mesh.h"

namespace bitstep {

inline constexpr uint32_t max_grid_samples = 4097;                  // along x or along z
inline constexpr uint32_t max_grid_cells = max_mesh_triangles / 2;  // two triangles each
inline constexpr Fixed min_grid_spacing = 0.01_fx;                  // m
inline constexpr Fixed max_grid_spacing = mesh_max_edge;            // m
inline constexpr Fixed max_grid_span = 16000.0_fx;                  // m, as a mesh's coordinates

struct HeightGrid {
  uint32_t columns = 0;         // samples along x
  uint32_t rows = 0;            // samples along z
  Fixed spacing_x, spacing_z;   // m between neighbouring samples
  std::vector<Fixed> heights;   // rows * columns, row by row: heights[j * columns + i]
  std::vector<uint32_t> holes;  // cells without ground, ascending: cell (i, j) is j * (columns - 1) + i

  uint32_t cell_count() const { return (columns - 1) * (rows - 1); }
  friend bool operator==(const HeightGrid&, const HeightGrid&) = default;
};

// The mesh of `grid` (its source_grid the grid), or why not
// ("columns: 1, a grid has 2 to 4097", "heights: 12 heights, not 4 x 4",
// "holes[2]: cell 40 of 36", "heights[7]: outside -16000..16000 m").
Result<std::shared_ptr<const TriangleMesh>> build_height_grid_mesh(HeightGrid grid);

}  // namespace bitstep
