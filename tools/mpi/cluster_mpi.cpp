// The cluster of an MPI build: MPI_COMM_WORLD when launched by mpirun or srun, else one
// process. Every MPI call of the tool is in this file.
#include <mpi.h>

#include <chrono>
#include <climits>
#include <cstdlib>
#include <thread>

#include <mccd/geometry/error.h>

#include "mpi/cluster.h"

namespace mccd::cli {

namespace {

/// Whether an MPI launcher started this process (Open MPI's mpirun, or a PMI / PMIx launcher
/// such as Slurm's srun).
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(v)) return true;
  return false;
}

void pause() { std::this_thread::sleep_for(std::chrono::microseconds(500)); }

void check(int rc, const char* what) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(rc, text, &len);
  throw Error(std::string(what) + ": " + std::string(text, std::size_t(len)));
}

class Mpi final : public Cluster {
 public:
  Mpi() {
    int provided = 0;
    // The batch's dispatcher thread on rank 0 makes the MPI calls while the main thread
    // works: calls come from more than one thread, never at once.
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    if (provided < MPI_THREAD_SERIALIZED) {
      MPI_Finalize();
      throw Error("the MPI library does not provide MPI_THREAD_SERIALIZED");
    }
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    std::atexit([] {
      int finalized = 0;
      MPI_Finalized(&finalized);
      if (!finalized) MPI_Finalize();
    });
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  [[noreturn]] void abort(int status) override {
    MPI_Abort(MPI_COMM_WORLD, status);
    std::exit(status);
  }
  void send(int to, int tag, const std::string& bytes) override {
    if (bytes.size() > std::size_t(INT_MAX)) throw Error("a message of " + std::to_string(bytes.size()) + " bytes is over MPI's 2 GiB");
    MPI_Request req;
    check(MPI_Isend(bytes.data(), int(bytes.size()), MPI_BYTE, to, tag, MPI_COMM_WORLD, &req), "MPI_Isend");
    for (int done = 0;;) {
      check(MPI_Test(&req, &done, MPI_STATUS_IGNORE), "MPI_Test");
      if (done) return;
      pause();
    }
  }
  std::string recv(int from, int tag, int* source) override {
    MPI_Status st;
    for (int flag = 0;;) {
      check(MPI_Iprobe(from == kAnySource ? MPI_ANY_SOURCE : from, tag, MPI_COMM_WORLD, &flag, &st), "MPI_Iprobe");
      if (flag) break;
      pause();
    }
    int count = 0;
    MPI_Get_count(&st, MPI_BYTE, &count);
    std::string bytes(std::size_t(count), '\0');
    check(MPI_Recv(bytes.data(), count, MPI_BYTE, st.MPI_SOURCE, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
    if (source) *source = st.MPI_SOURCE;
    return bytes;
  }

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace

Cluster& cluster() {
  static Cluster* const c =
      launched_by_mpi() ? static_cast<Cluster*>(new Mpi) : new SingleProcess("not started by mpirun");
  return *c;
}

bool built_with_mpi() { return true; }

}  // namespace mccd::cli
