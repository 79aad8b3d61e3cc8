// Implementation of LammpsDumpWriter.
#include "io/lammps_dump_writer.hpp"

#include <fmt/format.h>

#include "mesodpd/config_error.hpp"

namespace mesodpd {

LammpsDumpWriter::LammpsDumpWriter(std::filesystem::path path, const std::vector<std::string>& fields,
                                   bool append)
    : path_(std::move(path)), fields_(parse_trajectory_fields(fields, path_)) {
  out_.open(path_, append ? OutputFile::Mode::Append : OutputFile::Mode::Truncate);
}

void LammpsDumpWriter::write_frame(const FrameView& f) {
  check_frame_arrays(f, fields_, path_);
  const std::vector<std::size_t> order = order_by_id(f, path_);

  // Format the whole frame in memory, then write it once: one system call per frame, and a frame
  // is never left half-formatted in the stream if formatting throws.
  fmt::memory_buffer buf;
  auto out = std::back_inserter(buf);
  auto flag = [&](int d) { return f.periodic[static_cast<std::size_t>(d)] ? "pp" : "ff"; };
  fmt::format_to(out, "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS {} {} {}\n", f.step, f.n,
                 flag(0), flag(1), flag(2));
  for (int d = 0; d < 3; ++d) fmt::format_to(out, "{} {}\n", f.box_lo[d], f.box_lo[d] + f.box_len[d]);

  fmt::format_to(out, "ITEM: ATOMS");
  if (fields_.id) fmt::format_to(out, " id");
  if (fields_.species) fmt::format_to(out, " type");
  if (fields_.position) fmt::format_to(out, " x y z");
  if (fields_.velocity) fmt::format_to(out, " vx vy vz");
  if (fields_.force) fmt::format_to(out, " fx fy fz");
  if (fields_.image) fmt::format_to(out, " ix iy iz");
  std::vector<const FrameView::Extra*> extra;
  for (const std::string& name : fields_.extra) {
    extra.push_back(&extra_array(f, name));
    fmt::format_to(out, " {}", name);
  }
  fmt::format_to(out, "\n");

  for (const std::size_t i : order) {
    // Single spaces between columns and none at the end of the line: some readers split on ' '.
    bool first = true;
    auto sep = [&] {
      if (!first) buf.push_back(' ');
      first = false;
    };
    if (fields_.id) {
      sep();
      fmt::format_to(out, "{}", f.id[i]);
    }
    if (fields_.species) {
      sep();
      fmt::format_to(out, "{}", static_cast<std::int64_t>(f.species[i]) + 1);
    }
    if (fields_.position) {
      sep();
      fmt::format_to(out, "{} {} {}", f.x[i], f.y[i], f.z[i]);
    }
    if (fields_.velocity) {
      sep();
      fmt::format_to(out, "{} {} {}", f.vx[i], f.vy[i], f.vz[i]);
    }
    if (fields_.force) {
      sep();
      fmt::format_to(out, "{} {} {}", f.fx[i], f.fy[i], f.fz[i]);
    }
    if (fields_.image) {
      sep();
      fmt::format_to(out, "{} {} {}", f.ix[i], f.iy[i], f.iz[i]);
    }
    for (const FrameView::Extra* e : extra) {
      sep();
      visit_extra(*e, i, [&](auto v) {
        // Integers of one byte print as numbers, not characters.
        if constexpr (sizeof(v) == 1)
          fmt::format_to(out, "{}", static_cast<int>(v));
        else
          fmt::format_to(out, "{}", v);
      });
    }
    buf.push_back('\n');
  }

  out_.write(std::string_view(buf.data(), buf.size()));
  ++frames_written_;
}

}  // namespace mesodpd
