#include "skills/learning/runners/communicator.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>

#ifdef FLSD_WITH_MPI
#include <mpi.h>
#endif

namespace flsd {
namespace {

#ifdef FLSD_WITH_MPI
// Open MPI, MPICH and PMIx launchers (mpirun, srun) set one of these in every rank's environment.
// Without them the process was started alone, and MPI is not initialised at all.
bool LaunchedByMpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

// MPI from the first use to the end of the program. Only the main thread calls MPI (the
// environment threads never do), which is what MPI_THREAD_FUNNELED promises.
struct MpiSession {
  MpiSession() {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  }
  ~MpiSession() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
  }
};
#endif

// Adds one collective (its bytes and wall time) to a communicator's account.
class CollectiveTimer {
 public:
  CollectiveTimer(Communicator::Tally& tally, long bytes) : tally_(tally), start_(std::chrono::steady_clock::now()) {
    ++tally_.calls;
    tally_.bytes += bytes;
  }
  ~CollectiveTimer() {
    tally_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  Communicator::Tally& tally_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

const Communicator& Communicator::World() {
  static const Communicator world = [] {
#ifdef FLSD_WITH_MPI
    if (LaunchedByMpi()) {
      static MpiSession session;
      int rank = 0, size = 1;
      MPI_Comm_rank(MPI_COMM_WORLD, &rank);
      MPI_Comm_size(MPI_COMM_WORLD, &size);
      return Communicator(rank, size, /*world=*/true);
    }
#endif
    return Communicator(0, 1, /*world=*/false);
  }();
  return world;
}

const Communicator& Communicator::Self() {
  static const Communicator self(0, 1, /*world=*/false);
  return self;
}

void Communicator::Sum(double* values, int count) const {
  if (size_ == 1) return;
#ifdef FLSD_WITH_MPI
  CollectiveTimer timer(tally_, count * sizeof(double));
  MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
#endif
}

double Communicator::Sum(double value) const {
  Sum(&value, 1);
  return value;
}

bool Communicator::Any(bool value) const { return Sum(value ? 1.0 : 0.0) > 0.0; }

std::vector<double> Communicator::Gather(const std::vector<double>& local) const {
  if (size_ == 1) return local;
  std::vector<double> all(local.size() * size_);
#ifdef FLSD_WITH_MPI
  CollectiveTimer timer(tally_, local.size() * sizeof(double));
  MPI_Allgather(local.data(), static_cast<int>(local.size()), MPI_DOUBLE, all.data(), static_cast<int>(local.size()),
                MPI_DOUBLE, MPI_COMM_WORLD);
#endif
  return all;
}

void Communicator::AverageGradients(const std::vector<torch::Tensor>& parameters) const {
  if (size_ == 1) return;
  std::vector<torch::Tensor> grads;
  for (const torch::Tensor& p : parameters) {
    // A parameter this rank's loss did not reach still takes part, with a zero gradient.
    if (!p.grad().defined()) p.mutable_grad() = torch::zeros_like(p);
    grads.push_back(p.grad().reshape({-1}));
  }
  torch::Tensor flat = torch::cat(grads).to(torch::kFloat32).contiguous();
#ifdef FLSD_WITH_MPI
  {
    CollectiveTimer timer(tally_, flat.numel() * sizeof(float));
    MPI_Allreduce(MPI_IN_PLACE, flat.data_ptr<float>(), static_cast<int>(flat.numel()), MPI_FLOAT, MPI_SUM,
                  MPI_COMM_WORLD);
  }
#endif
  flat.div_(size_);
  int64_t offset = 0;
  for (const torch::Tensor& p : parameters) {
    const int64_t n = p.numel();
    p.mutable_grad().copy_(flat.slice(0, offset, offset + n).view_as(p));
    offset += n;
  }
}

void Communicator::Abort(const std::string& message) const {
  std::fprintf(stderr, "flsd: rank %d of %d: %s\n", rank_, size_, message.c_str());
  std::fflush(stderr);
#ifdef FLSD_WITH_MPI
  if (world_) MPI_Abort(MPI_COMM_WORLD, 1);
#endif
  std::exit(1);
}

Communicator::Tally Communicator::TakeTally() const {
  const Tally taken = tally_;
  tally_ = Tally{};
  return taken;
}

}  // namespace flsd
