// Block averages without knowing the run length: each sample is a row of `width` values, summed into
// equal-size blocks of samples. Up to 2B blocks are kept; when all 2B are full, neighbours are merged
// pairwise and the block size doubles, so between B and 2B - 1 full blocks of equal sample count exist
// at any time and memory stays O(B x width). PoiseuilleProfile (flow and count per bin) and the slab
// fit of BinnedFields (density per bin) use it.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/byte_buffer.hpp"
#include "mesodpd/config_error.hpp"

namespace mesodpd {

class BlockRows {
 public:
  BlockRows() = default;
  BlockRows(std::size_t width, std::size_t blocks) : width_(width), blocks_(blocks), sums_(2 * blocks * width, 0.0) {
    if (blocks < 2) throw std::invalid_argument("BlockRows: blocks must be >= 2");
  }

  // Adds one sample (width values) to the current block.
  void add(const double* row) {
    double* b = &sums_[full_ * width_];
    for (std::size_t k = 0; k < width_; ++k) b[k] += row[k];
    if (++in_current_ < block_size_) return;
    in_current_ = 0;
    if (++full_ < 2 * blocks_) return;
    for (std::size_t j = 0; j < blocks_; ++j)
      for (std::size_t k = 0; k < width_; ++k)
        sums_[j * width_ + k] = sums_[2 * j * width_ + k] + sums_[(2 * j + 1) * width_ + k];
    std::fill(sums_.begin() + static_cast<std::ptrdiff_t>(blocks_ * width_), sums_.end(), 0.0);
    full_ = blocks_;
    block_size_ *= 2;
  }

  std::size_t full_blocks() const { return full_; }
  std::size_t samples_per_block() const { return block_size_; }
  // The summed rows of full block k < full_blocks().
  const double* block(std::size_t k) const { return &sums_[k * width_]; }

  // The whole state (2B rows of sums, samples in the unfinished block), for checkpoints.
  std::size_t in_current() const { return in_current_; }
  const std::vector<double>& sums() const { return sums_; }
  void restore(std::size_t block_size, std::size_t full, std::size_t in_current, std::vector<double> sums,
               const std::string& context) {
    if (sums.size() != 2 * blocks_ * width_ || full >= 2 * blocks_ || block_size == 0 || in_current >= block_size)
      throw ConfigError(context + ": inconsistent block-average state");
    block_size_ = block_size;
    full_ = full;
    in_current_ = in_current;
    sums_ = std::move(sums);
  }

  void save(ByteWriter& w) const {
    w.put<std::uint64_t>(width_);
    w.put<std::uint64_t>(blocks_);
    w.put<std::uint64_t>(block_size_);
    w.put<std::uint64_t>(full_);
    w.put<std::uint64_t>(in_current_);
    w.put_vector(sums_);
  }
  void load(ByteReader& r, const std::string& context) {
    const auto width = r.get<std::uint64_t>(), blocks = r.get<std::uint64_t>();
    if (width != width_ || blocks != blocks_)
      throw ConfigError(context + ": block averages recorded with other bins or blocks");
    const auto block_size = r.get<std::uint64_t>(), full = r.get<std::uint64_t>(), in_current = r.get<std::uint64_t>();
    restore(block_size, full, in_current, r.get_vector<double>(), context);
  }

 private:
  std::size_t width_ = 0, blocks_ = 2;
  std::size_t block_size_ = 1, full_ = 0, in_current_ = 0;
  std::vector<double> sums_;
};

}  // namespace mesodpd
