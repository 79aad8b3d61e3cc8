// VTK XML image data writer (see vtk_image.hpp).
#include "io/vtk_image.hpp"

#include <fmt/format.h>

#include <bit>
#include <cstring>
#include <ostream>
#include <stdexcept>

#include "io/atomic_file.hpp"

namespace mesodpd {

std::string base64_encode(const void* data, std::size_t bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* in = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes; i += 3) {
    const unsigned v = (unsigned{in[i]} << 16) | (unsigned{in[i + 1]} << 8) | in[i + 2];
    for (int k = 3; k >= 0; --k) out += kAlphabet[(v >> (6 * k)) & 63];
  }
  if (const std::size_t rest = bytes - i; rest > 0) {
    const unsigned v = (unsigned{in[i]} << 16) | (rest == 2 ? unsigned{in[i + 1]} << 8 : 0u);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += rest == 2 ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

void write_vti(const std::filesystem::path& path, const VtkImage& image) {
  static_assert(std::endian::native == std::endian::little, "write_vti writes the host's bytes as LittleEndian");
  std::size_t n = 1;
  for (int c : image.cells) {
    if (c < 1) throw std::invalid_argument("write_vti: every axis needs at least one cell");
    n *= static_cast<std::size_t>(c);
  }
  for (const VtkCellArray& a : image.arrays)
    if ((a.components != 1 && a.components != 3) || a.values.size() != n * static_cast<std::size_t>(a.components))
      throw std::invalid_argument(fmt::format("write_vti: array '{}' has {} values for {} cells x {} components",
                                              a.name, a.values.size(), n, a.components));
  const auto& c = image.cells;
  const std::string extent = fmt::format("0 {} 0 {} 0 {}", c[0], c[1], c[2]);
  write_file_atomically(path, [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
       << fmt::format("  <ImageData WholeExtent=\"{}\" Origin=\"{:.17g} {:.17g} {:.17g}\" Spacing=\"{:.17g} {:.17g} {:.17g}\">\n",
                      extent, image.origin[0], image.origin[1], image.origin[2], image.spacing[0], image.spacing[1],
                      image.spacing[2]);
    if (!image.field_data.empty()) {
      os << "    <FieldData>\n";
      for (const auto& [name, value] : image.field_data)
        os << fmt::format("      <DataArray type=\"Float64\" Name=\"{}\" NumberOfTuples=\"1\" format=\"ascii\">{:.17g}</DataArray>\n",
                          name, value);
      os << "    </FieldData>\n";
    }
    os << fmt::format("    <Piece Extent=\"{}\">\n", extent);
    std::string scalars, vectors;
    for (const VtkCellArray& a : image.arrays) {
      if (a.components == 1 && scalars.empty()) scalars = a.name;
      if (a.components == 3 && vectors.empty()) vectors = a.name;
    }
    os << "      <CellData";
    if (!scalars.empty()) os << " Scalars=\"" << scalars << "\"";
    if (!vectors.empty()) os << " Vectors=\"" << vectors << "\"";
    os << ">\n";
    for (const VtkCellArray& a : image.arrays) {
      const std::uint64_t bytes = a.values.size() * sizeof(double);
      os << fmt::format("        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"binary\">",
                        a.name, a.components)
         << base64_encode(&bytes, sizeof bytes) << base64_encode(a.values.data(), bytes) << "</DataArray>\n";
    }
    os << "      </CellData>\n    </Piece>\n  </ImageData>\n</VTKFile>\n";
  });
}

}  // namespace mesodpd
