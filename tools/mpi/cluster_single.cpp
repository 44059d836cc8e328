// The cluster of a build without MPI: one process, rank 0 of 1.
#include "mpi/cluster.h"

#include <cstdlib>

#include <mccd/geometry/error.h>

namespace mccd::cli {

namespace {

class Single final : public Cluster {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  [[noreturn]] void abort(int status) override { std::exit(status); }
  void send(int, int, const std::string&) override { throw Error("no other rank to send to (built without MPI)"); }
  std::string recv(int, int, int*) override { throw Error("no other rank to receive from (built without MPI)"); }
};

}  // namespace

Cluster& cluster() {
  static Single single;
  return single;
}

bool built_with_mpi() { return false; }

}  // namespace mccd::cli
