#pragma once
// One OpenMP parallel region per step (issue 19 point 2). Every loop of a step goes through these helpers,
// which run it
//   - outside a team: as its own `parallel for` (a fork/join per loop, as before);
//   - inside run_team(): as a worksharing loop of the step's one region (a barrier per loop, no fork);
//   - inside a team_single() body: serially (the region's other threads wait at the single's barrier).
// Loops keep the same schedule and the same per-particle summation order in every mode, so results are
// bitwise the same (test_team). Rules for code that runs inside run_team (docs/architecture.md):
//   - every statement runs on every thread: shared state is written only inside team_single() or by the
//     loop helpers (each iteration its own slot); a function with its own `#pragma omp parallel` is called
//     inside team_single() (it then runs on one thread, correct but serial);
//   - exceptions are thrown only inside team_single() bodies: every thread leaves the region together and
//     run_team rethrows the first one on the caller's thread.
#include <algorithm>
#include <exception>
#include <utility>

#include <omp.h>

namespace varsph {
namespace team_detail {

struct TeamState {
  std::exception_ptr error;  // from a team_single body; every thread checks it after the single's barrier
  double slot[2] = {0, 0};   // team_max2's shared accumulators
};
struct Abort {};  // thrown on every thread after a team_single body failed; caught by run_team

inline thread_local TeamState* tls_team = nullptr;  // set for the threads of a run_team region
inline thread_local int tls_serial = 0;             // > 0 inside a team_single body

}  // namespace team_detail

// True on a thread of a run_team region, outside its single sections: loops share the work of the team.
inline bool in_team() { return team_detail::tls_team != nullptr && team_detail::tls_serial == 0; }
// True inside a team_single body: loops run serially on this thread.
inline bool in_team_single() { return team_detail::tls_team != nullptr && team_detail::tls_serial > 0; }

// Runs body() on every thread of one parallel region (or directly when a team is already running or one
// thread is all there is). Rethrows the first exception of a team_single body.
template <class F>
void run_team(F&& body) {
  if (team_detail::tls_team != nullptr || omp_get_max_threads() == 1) {
    body();
    return;
  }
  team_detail::TeamState state;
#pragma omp parallel
  {
    team_detail::tls_team = &state;
    try {
      body();
    } catch (const team_detail::Abort&) {
      // the exception is in state.error
    } catch (...) {
      // thrown outside a team_single (against the rules above): keep it; the others may be waiting, so this
      // is a last resort that terminates rather than hangs only when every thread throws alike
#pragma omp critical(varsph_team_error)
      if (!state.error) state.error = std::current_exception();
    }
    team_detail::tls_team = nullptr;
  }
  if (state.error) std::rethrow_exception(state.error);
}

// body() once: by one thread of the team (the others wait at its barrier), or directly outside a team.
template <class F>
void team_single(F&& body) {
  if (!in_team()) {
    body();
    return;
  }
  team_detail::TeamState* st = team_detail::tls_team;
#pragma omp single
  {
    ++team_detail::tls_serial;
    try {
      body();
    } catch (...) {
      st->error = std::current_exception();
    }
    --team_detail::tls_serial;
  }
  if (st->error) throw team_detail::Abort{};  // every thread, after the barrier: the region ends together
}

// The barrier of a team (nothing outside one).
inline void team_barrier() {
  if (in_team()) {
#pragma omp barrier
  }
}

// for i in [0, n): f(i), each iteration writing only its own slots; static schedule in every mode.
template <class F>
void team_for(long n, F&& f) {
  if (in_team()) {
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) f(i);
  } else if (in_team_single()) {
    for (long i = 0; i < n; ++i) f(i);
  } else {
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) f(i);
  }
}

// The same with schedule(dynamic, 4): the pair sweeps over cell blocks of uneven cost.
template <class F>
void team_for_dynamic(long n, F&& f) {
  if (in_team()) {
#pragma omp for schedule(dynamic, 4)
    for (long i = 0; i < n; ++i) f(i);
  } else if (in_team_single()) {
    for (long i = 0; i < n; ++i) f(i);
  } else {
#pragma omp parallel for schedule(dynamic, 4)
    for (long i = 0; i < n; ++i) f(i);
  }
}

// Two maxima in one loop: f(i, m0, m1) raises m0 and m1 (from 0). A max is exact in any order, so every
// mode gives the same values.
template <class F>
std::pair<double, double> team_max2(long n, F&& f) {
  double m0 = 0, m1 = 0;
  if (in_team()) {
    team_detail::TeamState* st = team_detail::tls_team;
#pragma omp single
    st->slot[0] = st->slot[1] = 0;
#pragma omp for schedule(static) nowait
    for (long i = 0; i < n; ++i) f(i, m0, m1);
#pragma omp critical(varsph_team_max)
    {
      st->slot[0] = std::max(st->slot[0], m0);
      st->slot[1] = std::max(st->slot[1], m1);
    }
#pragma omp barrier
    m0 = st->slot[0];
    m1 = st->slot[1];
#pragma omp barrier  // nobody resets the slots (next team_max2) before every thread has read them
  } else if (in_team_single()) {
    for (long i = 0; i < n; ++i) f(i, m0, m1);
  } else {
#pragma omp parallel for schedule(static) reduction(max : m0, m1)
    for (long i = 0; i < n; ++i) f(i, m0, m1);
  }
  return {m0, m1};
}

}  // namespace varsph
