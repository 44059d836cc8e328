// The cluster of a build without MPI: one process, rank 0 of 1.
#include "mpi/cluster.h"

namespace mccd::cli {

Cluster& cluster() {
  static SingleProcess single("built without MPI");
  return single;
}

bool built_with_mpi() { return false; }

}  // namespace mccd::cli
