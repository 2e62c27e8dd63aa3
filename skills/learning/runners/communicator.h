#pragma once
// The ranks of a data-parallel training job. Under mpirun (or any MPI launcher: Slurm, a hostfile)
// every rank runs its own environments and the ranks agree on every update through MPI
// collectives; alone, every collective is the identity, so one process trains exactly as it would
// without MPI. MPI is optional when building (FLSD_WITH_MPI) and when running.

#include <torch/torch.h>

#include <string>
#include <vector>

namespace flsd {

class Communicator {
 public:
  // The job this process was launched in: MPI's world when built with MPI and started by an MPI
  // launcher, this process alone otherwise. MPI is initialised on the first call and finalised at exit.
  static const Communicator& World();
  // This process alone, whatever the job (the reference side of equivalence tests).
  static const Communicator& Self();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool leader() const { return rank_ == 0; }

  // Element-wise sum over the ranks, in place.
  void Sum(double* values, int count) const;
  double Sum(double value) const;
  // True on every rank if it is true on any.
  bool Any(bool value) const;
  // Every rank's `local` (the same length on all), concatenated in rank order, on every rank.
  std::vector<double> Gather(const std::vector<double>& local) const;
  // Replaces each parameter's gradient by its mean over the ranks (one message for all of them):
  // with equal shares of a batch, the gradient of the whole batch's mean loss.
  void AverageGradients(const std::vector<torch::Tensor>& parameters) const;

  // Ends the whole job with `message` (naming this rank) on stderr; a failing rank calls it so that
  // the others do not wait in a collective for ever.
  [[noreturn]] void Abort(const std::string& message) const;

  // What the collectives since the last call cost (nothing alone): the price of data parallelism.
  // Seconds include waiting for the slowest rank.
  struct Tally {
    double seconds = 0.0;
    long calls = 0;
    long bytes = 0;  // this rank's contribution
  };
  Tally TakeTally() const;

 private:
  Communicator(int rank, int size, bool world) : rank_(rank), size_(size), world_(world) {}

  int rank_, size_;
  bool world_;  // MPI_COMM_WORLD (size may be 1) rather than this process alone
  mutable Tally tally_;
};

}  // namespace flsd
