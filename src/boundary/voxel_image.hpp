// Voxel images of a solid, the "shadow grid" of seed 000 Sect. 3.2.2 (0 = fluid, 1 = solid): the two
// file formats (docs/config.md "Image files"), and the image as a Shape with a signed distance from a
// Euclidean distance transform and normals from the gradient of the smoothed indicator.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "boundary/geometry.hpp"

namespace mesodpd {

// A grid of cells, x fastest: solid[(k * n[1] + j) * n[0] + i] is 1 for a solid cell, 0 for fluid.
struct VoxelGrid {
  std::array<int, 3> n{0, 0, 0};
  std::vector<std::uint8_t> solid;
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(n[1]) + static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(n[0]) + static_cast<std::size_t>(i);
  }
};

// A PGM image (P2 text or P5 binary, any maxval): n = {width, height, 1}; a pixel is solid when its
// value is nonzero. Row 0 of the returned grid is the file's LAST row (the bottom of the picture), so
// that the picture keeps its orientation when its second axis points up. Throws ConfigError naming
// the file and the problem.
VoxelGrid read_pgm(const std::string& file);

// A 3-D MESODPD-VOXELS file (header lines "MESODPD-VOXELS 1", "size NX NY NZ",
// "encoding ascii|binary", "data", then NX*NY*NZ cells x fastest: '0'/'1' characters with any
// whitespace between them, or bytes 0/1). Throws ConfigError naming the file and the problem.
VoxelGrid read_voxels(const std::string& file);

// The image of `spec` (kind Image) laid over the box: a .pgm file is extruded along spec.axis (its
// columns along the first other axis in x, y, z order, its rows along the second), any other file is
// read as MESODPD-VOXELS. Each cell is voxel_size wide; the image must cover the box exactly.
VoxelGrid load_image(const ShapeSpec& spec, const Box& box, const std::string& key);

class ImageShape final : public Shape {
 public:
  ImageShape(const VoxelGrid& grid, const Box& box);
  double sdf(const Vec3& p) const override;
  // Minus the normalised gradient of the smoothed indicator (seed 000 Sect. 3.2.2): the indicator rises
  // into the solid, so this points into the fluid.
  Vec3 normal(const Vec3& p) const override;
  // Trilinear interpolation of distances at cell centres: up to 1 per unit length along each axis.
  double lipschitz() const override { return 1.7320508075688772; }

 private:
  // Trilinear interpolation of a cell-centred field, periodic along periodic axes, clamped otherwise.
  double interpolate(const std::vector<float>& f, const Vec3& p) const;
  std::array<int, 3> n_;
  std::array<double, 3> h_;  // cell size
  std::array<bool, 3> periodic_;
  std::vector<float> sdf_;       // signed distance at cell centres
  std::vector<float> gradient_[3];  // gradient of the smoothed indicator at cell centres
};

}  // namespace mesodpd
