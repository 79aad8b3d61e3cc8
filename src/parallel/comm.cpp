// Comm on MPI (MESODPD_HAVE_MPI) or on one rank.
#include "parallel/comm.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "mesodpd/config_error.hpp"

#ifdef MESODPD_HAVE_MPI
#include <mpi.h>
#endif

namespace mesodpd {

Comm Comm::world() {
  Comm c;
#ifdef MESODPD_HAVE_MPI
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  if (initialised && !finalised) {
    c.mpi_ = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &c.rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &c.size_);
  }
#endif
  return c;
}

#ifdef MESODPD_HAVE_MPI
namespace {
void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI error in ") + what);
}
// MPI counts are int: large messages go in pieces of at most 1 GiB.
constexpr std::size_t kChunk = std::size_t{1} << 30;

// A user-defined sum for 128-bit integers (MPI has no such type).
__extension__ void sum_int128(void* in, void* inout, int* len, MPI_Datatype*) {
  __extension__ auto* a = static_cast<__int128*>(in);
  __extension__ auto* b = static_cast<__int128*>(inout);
  for (int k = 0; k < *len; ++k) b[k] += a[k];
}
}  // namespace
#endif

// Every reduction goes through here: in place over all ranks, nothing to do on one rank. The MPI
// type and operation are named by small codes so that the header needs no <mpi.h>.
void Comm::allreduce(void* data, std::size_t count, ReduceType type, ReduceOp op) const {
#ifdef MESODPD_HAVE_MPI
  if (!mpi_ || size_ < 2 || count == 0) return;
  MPI_Datatype dtype = MPI_INT64_T;
  MPI_Op mop = op == ReduceOp::Sum ? MPI_SUM : (op == ReduceOp::Min ? MPI_MIN : MPI_MAX);
  bool custom = false;
  switch (type) {
    case ReduceType::Int64: dtype = MPI_INT64_T; break;
    case ReduceType::Uint64: dtype = MPI_UINT64_T; break;
    case ReduceType::Double: dtype = MPI_DOUBLE; break;
    case ReduceType::Int128:
      // MPI has no 128-bit integer: a 16-byte type with a user-defined sum.
      check(MPI_Type_contiguous(16, MPI_BYTE, &dtype), "Type_contiguous");
      MPI_Type_commit(&dtype);
      MPI_Op_create(&sum_int128, 1, &mop);
      custom = true;
      break;
  }
  const int rc = MPI_Allreduce(MPI_IN_PLACE, data, static_cast<int>(count), dtype, mop, MPI_COMM_WORLD);
  if (custom) {
    MPI_Op_free(&mop);
    MPI_Type_free(&dtype);
  }
  check(rc, "Allreduce");
#else
  (void)data;
  (void)count;
  (void)type;
  (void)op;
#endif
}

void Comm::sum(std::span<std::int64_t> v) const { allreduce(v.data(), v.size(), ReduceType::Int64, ReduceOp::Sum); }
void Comm::sum(std::span<std::uint64_t> v) const { allreduce(v.data(), v.size(), ReduceType::Uint64, ReduceOp::Sum); }
void Comm::sum(std::span<double> v) const { allreduce(v.data(), v.size(), ReduceType::Double, ReduceOp::Sum); }
__extension__ void Comm::sum(std::span<__int128> v) const {
  allreduce(v.data(), v.size(), ReduceType::Int128, ReduceOp::Sum);
}
std::uint64_t Comm::min(std::uint64_t v) const {
  allreduce(&v, 1, ReduceType::Uint64, ReduceOp::Min);
  return v;
}
std::uint64_t Comm::max(std::uint64_t v) const {
  allreduce(&v, 1, ReduceType::Uint64, ReduceOp::Max);
  return v;
}

std::vector<std::byte> Comm::exchange(int dest, int src, int tag, std::span<const std::byte> send) const {
#ifdef MESODPD_HAVE_MPI
  if (mpi_ && size_ > 1) {
    if (dest < 0) dest = MPI_PROC_NULL;
    if (src < 0) src = MPI_PROC_NULL;
    std::uint64_t out_n = send.size(), in_n = 0;
    check(MPI_Sendrecv(&out_n, 1, MPI_UINT64_T, dest, tag, &in_n, 1, MPI_UINT64_T, src, tag, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE),
          "Sendrecv");
    // Receives and sends are posted separately: dest and src differ when a split axis has more than
    // two ranks, so the two directions have unrelated sizes.
    std::vector<std::byte> recv(in_n);
    std::vector<MPI_Request> requests;
    for (std::size_t off = 0; off < in_n; off += kChunk) {
      requests.emplace_back();
      check(MPI_Irecv(recv.data() + off, static_cast<int>(std::min(kChunk, in_n - off)), MPI_BYTE, src, tag,
                      MPI_COMM_WORLD, &requests.back()),
            "Irecv");
    }
    for (std::size_t off = 0; off < out_n; off += kChunk) {
      requests.emplace_back();
      check(MPI_Isend(send.data() + off, static_cast<int>(std::min(kChunk, out_n - off)), MPI_BYTE, dest, tag,
                      MPI_COMM_WORLD, &requests.back()),
            "Isend");
    }
    check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "Waitall");
    return recv;
  }
#endif
  (void)dest;
  (void)tag;
  if (src < 0) return {};
  return std::vector<std::byte>(send.begin(), send.end());
}

std::vector<std::byte> Comm::gather(std::span<const std::byte> send) const {
#ifdef MESODPD_HAVE_MPI
  if (mpi_ && size_ > 1) {
    // Point-to-point to the root in rank order: no int overflow of MPI_Gatherv displacements.
    constexpr int kTag = 7001;
    std::vector<std::byte> all;
    if (root()) {
      all.assign(send.begin(), send.end());
      for (int r = 1; r < size_; ++r) {
        std::uint64_t n = 0;
        check(MPI_Recv(&n, 1, MPI_UINT64_T, r, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "Recv");
        const std::size_t base = all.size();
        all.resize(base + n);
        for (std::size_t off = 0; off < n; off += kChunk)
          check(MPI_Recv(all.data() + base + off, static_cast<int>(std::min(kChunk, n - off)), MPI_BYTE, r, kTag,
                         MPI_COMM_WORLD, MPI_STATUS_IGNORE),
                "Recv");
      }
    } else {
      const std::uint64_t n = send.size();
      check(MPI_Send(&n, 1, MPI_UINT64_T, 0, kTag, MPI_COMM_WORLD), "Send");
      for (std::size_t off = 0; off < n; off += kChunk)
        check(MPI_Send(send.data() + off, static_cast<int>(std::min(kChunk, n - off)), MPI_BYTE, 0, kTag,
                       MPI_COMM_WORLD),
              "Send");
    }
    return all;
  }
#endif
  return std::vector<std::byte>(send.begin(), send.end());
}

void Comm::broadcast(std::vector<std::byte>& bytes) const {
#ifdef MESODPD_HAVE_MPI
  if (mpi_ && size_ > 1) {
    std::uint64_t n = bytes.size();
    check(MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "Bcast");
    bytes.resize(n);
    for (std::size_t off = 0; off < n; off += kChunk)
      check(MPI_Bcast(bytes.data() + off, static_cast<int>(std::min(kChunk, n - off)), MPI_BYTE, 0, MPI_COMM_WORLD),
            "Bcast");
  }
#else
  (void)bytes;
#endif
}

void Comm::broadcast(std::string& text) const {
  if (size_ == 1) return;
  std::vector<std::byte> b(text.size());
  if (!text.empty()) std::memcpy(b.data(), text.data(), text.size());
  broadcast(b);
  text.assign(reinterpret_cast<const char*>(b.data()), b.size());
}

void Comm::barrier() const {
#ifdef MESODPD_HAVE_MPI
  if (mpi_ && size_ > 1) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

void Comm::raise_if_any(std::string error) const {
  broadcast(error);
  if (!error.empty()) throw ConfigError(error);
}

void Comm::abort(int code) const {
#ifdef MESODPD_HAVE_MPI
  if (mpi_ && size_ > 1) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

MpiSession::MpiSession(int& argc, char**& argv) {
#ifdef MESODPD_HAVE_MPI
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
#else
  (void)argc;
  (void)argv;
#endif
}

MpiSession::~MpiSession() {
#ifdef MESODPD_HAVE_MPI
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (!finalised) MPI_Finalize();
#endif
}

}  // namespace mesodpd
