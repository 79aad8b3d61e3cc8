// The communicator every distributed module talks through: MPI_COMM_WORLD when the build has MPI and the
// process was started under MPI, otherwise a single rank. Only the few collective operations the engine
// needs are offered, each on typed data, so that no other file includes <mpi.h>.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace mesodpd {

class Comm {
 public:
  // The world communicator if MPI is initialised (MpiSession), else a serial one.
  static Comm world();
  static Comm serial() { return Comm(); }

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  bool distributed() const { return size_ > 1; }

  // In-place sums over all ranks (integers: the result does not depend on the rank count or order).
  void sum(std::span<std::int64_t> v) const;
  void sum(std::span<std::uint64_t> v) const;
  void sum(std::span<double> v) const;  // only for values that are nonzero on a single rank
  __extension__ void sum(std::span<__int128> v) const;
  std::uint64_t min(std::uint64_t v) const;
  std::uint64_t max(std::uint64_t v) const;

  // Sends `send` to rank `dest` and returns what rank `src` sent with the same tag. A negative rank
  // means no partner on that side (the end of a bounded axis): nothing is sent, or nothing received.
  std::vector<std::byte> exchange(int dest, int src, int tag, std::span<const std::byte> send) const;
  // Concatenation of every rank's bytes in rank order, on the root only (empty elsewhere).
  std::vector<std::byte> gather(std::span<const std::byte> send) const;
  // The root's bytes on every rank.
  void broadcast(std::vector<std::byte>& bytes) const;
  void broadcast(std::string& text) const;
  void barrier() const;

  // Runs `work` on the root. An exception there is re-thrown on every rank as a ConfigError with its
  // message, so a failed file operation on the root stops all ranks instead of leaving them waiting.
  template <class F>
  void on_root(F&& work) const {
    std::string error;
    if (root()) {
      try {
        work();
      } catch (const std::exception& e) {
        error = e.what();
        if (error.empty()) error = "unknown error";
      }
    }
    raise_if_any(error);
  }

  // Aborts all ranks with `code` (used when one rank fails outside a collective operation).
  [[noreturn]] void abort(int code) const;

 private:
  enum class ReduceType { Int64, Uint64, Double, Int128 };
  enum class ReduceOp { Sum, Min, Max };
  Comm() = default;
  void allreduce(void* data, std::size_t count, ReduceType type, ReduceOp op) const;
  void raise_if_any(std::string error) const;

  int rank_ = 0;
  int size_ = 1;
  bool mpi_ = false;
};

// MPI's lifetime for a program (MPI_Init_thread with funneled threads, MPI_Finalize). Does nothing in a
// build without MPI. Construct one at the top of main().
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

}  // namespace mesodpd
