#pragma once
/// @file The ranks of a run: this process's place among the processes `mpirun` or `srun`
/// started, and byte messages between them. The only MPI-facing interface of the tool; the
/// library knows nothing of it.
///
/// Built with MCCD_MPI (tools/mpi/cluster_mpi.cpp), MPI is initialised on first use only when
/// the process was launched by an MPI launcher (Open MPI's or PMI/PMIx variables in the
/// environment), so that a plain `mccd run` starts no MPI at all; otherwise, and in a build
/// without MPI (cluster_single.cpp), the cluster is this one process, rank 0 of 1.
///
/// Waiting for a message polls with short sleeps instead of spinning, so that a waiting rank
/// leaves its core to the ranks (and the oneTBB threads) still working.
#include <cstdlib>
#include <string>

#include <mccd/geometry/error.h>

namespace mccd::cli {

class Cluster {
 public:
  static constexpr int kAnySource = -1;
  virtual ~Cluster() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// Sends `bytes` to rank `to` with `tag`; returns once the buffer may be reused.
  virtual void send(int to, int tag, const std::string& bytes) = 0;
  /// Waits for a message with `tag` from `from` (or kAnySource) and returns it; `source`, if
  /// given, receives the sender's rank.
  virtual std::string recv(int from, int tag, int* source = nullptr) = 0;
  /// Ends every rank of the run at once with `status` (MPI_Abort); for an error that leaves
  /// the others waiting. A single process just exits.
  [[noreturn]] virtual void abort(int status) = 0;
  /// "rank 1 of 4" or "" for a single process.
  std::string where() const {
    return size() > 1 ? "rank " + std::to_string(rank()) + " of " + std::to_string(size()) : std::string();
  }
};

/// One process, rank 0 of 1; sending or receiving is refused, saying `why` there is no other
/// rank ("not started by mpirun", "built without MPI").
class SingleProcess final : public Cluster {
 public:
  explicit SingleProcess(const char* why) : why_(why) {}
  int rank() const override { return 0; }
  int size() const override { return 1; }
  [[noreturn]] void abort(int status) override { std::exit(status); }
  void send(int, int, const std::string&) override {
    throw Error(std::string("no other rank to send to (") + why_ + ")");
  }
  std::string recv(int, int, int*) override {
    throw Error(std::string("no other rank to receive from (") + why_ + ")");
  }

 private:
  const char* why_;
};

/// This process's cluster (initialised on first call; MPI finalised at exit).
Cluster& cluster();

/// Whether the tool was built with MPI.
bool built_with_mpi();

}  // namespace mccd::cli
