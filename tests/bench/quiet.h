// Timings taken alone while `make bench` runs two lanes of programs at once (tests/bench/run.sh).
//
// Usage:
//   {
//       BenchQuiet quiet;           // the other lanes stop here
//       ... the timed work ...
//   }                               // and go on here
//
// run.sh starts each lane in its own process group and lists the groups, one per line, in the
// file named by $SEPAL_BENCH_LANES. A BenchQuiet takes an exclusive lock on that file (so two
// lanes' timings never overlap), stops every other lane's group (SIGSTOP: the processes and
// all their threads, llvmpipe's included), and gives them 50 ms to come off the cores; leaving
// it resumes them (SIGCONT) and unlocks. A stopped lane's wall clock runs on: what it times
// outside a quiet section of its own (phase seconds, per-decomposition seconds: diagnostics)
// includes the time it was stopped and shared the machine, so every figure a user plans with
// is timed inside one. Without the variable (a program run by hand, or run.sh's first
// phase, where programs run one at a time) it does nothing. A program that dies inside a
// section cannot leave the others stopped: each lane's script resumes every lane when a
// program ends (run.sh).
// Limits: POSIX (flock, kill on process groups); sections do not nest.
#pragma once
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

class BenchQuiet {
  public:
    BenchQuiet() {
        const char* path = std::getenv("SEPAL_BENCH_LANES");
        if (!path || !*path) return;
        fd_ = open(path, O_RDONLY | O_CLOEXEC);
        if (fd_ < 0) return;
        if (flock(fd_, LOCK_EX) != 0) {
            close(fd_);
            fd_ = -1;
            return;
        }
        // Read after locking: run.sh writes the list before any lane starts a program.
        if (FILE* f = std::fopen(path, "r")) {
            long g = 0;
            while (std::fscanf(f, "%ld", &g) == 1)
                if (g > 1 && pid_t(g) != getpgrp()) groups_.push_back(pid_t(g));
            std::fclose(f);
        }
        for (pid_t g : groups_) kill(-g, SIGSTOP);
        if (!groups_.empty()) {
            const timespec settle = {0, 50 * 1000 * 1000};
            nanosleep(&settle, nullptr);
        }
    }
    ~BenchQuiet() {
        for (pid_t g : groups_) kill(-g, SIGCONT);
        if (fd_ >= 0) {
            flock(fd_, LOCK_UN);
            close(fd_);
        }
    }
    BenchQuiet(const BenchQuiet&) = delete;
    BenchQuiet& operator=(const BenchQuiet&) = delete;

  private:
    int fd_ = -1;
    std::vector<pid_t> groups_;
};
