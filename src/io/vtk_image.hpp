// VTK XML image data (.vti) for ParaView, VisIt and the `vtk` Python package: a regular grid whose
// cells carry scalar and vector arrays (binned fields; later voxel geometries).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace mesodpd {

struct VtkCellArray {
  std::string name;
  int components = 1;         // 1 (scalar) or 3 (vector)
  std::vector<double> values; // cells x components, x fastest, then y, then z; NaN allowed
};

struct VtkImage {
  std::array<int, 3> cells{1, 1, 1};         // cells along x, y, z
  std::array<double, 3> origin{0, 0, 0};     // corner of the first cell
  std::array<double, 3> spacing{1, 1, 1};    // cell size
  std::vector<VtkCellArray> arrays;          // CellData
  std::vector<std::pair<std::string, double>> field_data;  // one-value FieldData arrays (samples, steps)
};

// Writes `image` atomically as a VTK XML ImageData file (version 1.0, little-endian, UInt64 headers),
// each CellData array Float64 in inline base64 ("binary") form: the 8-byte byte count and the data are
// base64-encoded separately, as VTK's own writer does. Binary rather than ASCII so that NaN (an empty
// bin) reads back as NaN. Throws std::invalid_argument on inconsistent sizes.
void write_vti(const std::filesystem::path& path, const VtkImage& image);

// Standard base64 (RFC 4648) with '=' padding.
std::string base64_encode(const void* data, std::size_t bytes);

}  // namespace mesodpd
