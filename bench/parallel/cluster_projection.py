#!/usr/bin/env python3
"""The cluster projection of docs/performance.md ("Beyond one machine"): parallel efficiency of a 3D
dam break on P ranks as a function of particles per rank n, from figures measured on this machine and a
STATED network model. Prints a table and the smallest n with efficiency >= the target. A model, not a
measurement: every input is named below with where it comes from.

  python3 bench/parallel/cluster_projection.py                       # the figures of docs/performance.md
  python3 bench/parallel/cluster_projection.py --latency-us 2 --gbit 100 --ranks-per-nic 32

Per step and rank (an interior rank of a 3D box decomposition, 26 neighbour ranks):
  compute   T_c = imbalance * n * t_p                         t_p: serial ns per particle-step (measured)
  ghosts    g(n) = (n^(1/3) + 2 delta)^3 - n                   delta: halo depth in particle layers
                                                              (support + skin = 2 cells = 2.6 dx; checked
                                                              against the measured ghost counts)
  halo CPU  T_g = g * t_g                                     t_g: CPU time per ghost and step (packing,
                                                              unpacking, ghost rebuild: measured)
  network   T_n = m * alpha + g * b_g * ranks_per_nic / beta  m: messages per step (measured count of
                                                              point-to-point sends per neighbour, x 26);
                                                              b_g: bytes per ghost per step (measured)
  reduce    T_r = r * 2 log2(P) * alpha                       r: allreduces per step (measured count)
  efficiency E = n t_p / (T_c + T_g + T_n + T_r - T_h)
  hidden    T_h = min(T_refresh, f_int T_c)                   overlap (docs/parallel.md "Overlap"): the
                                                              halo refresh's network time (1 of the m/26
                                                              messages per neighbour, 64 of the b_g bytes
                                                              per ghost) behind the interior sweep, f_int
                                                              = (n^(1/3) - 2 delta)^3 / n of the work. By
                                                              default only its latency: a rendezvous
                                                              message moves while the library is entered
                                                              (measured: bench_mpi_overlap), so its bytes
                                                              hide only with --async-progress (a progress
                                                              thread or an offloading network, assumed).
                                                              --no-overlap: T_h = 0 (the 05:40 figures).
"""
import argparse
import math


def efficiency(n, a, P):
    ghosts = (n ** (1.0 / 3.0) + 2 * a.delta) ** 3 - n
    t_c = a.imbalance * n * a.t_p_ns * 1e-9
    t_g = ghosts * a.t_g_ns * 1e-9
    beta = a.gbit * 1e9 / 8  # bytes/s of one network link
    t_n = a.messages_per_neighbour * a.neighbours * a.latency_us * 1e-6 + ghosts * a.bytes_per_ghost * a.ranks_per_nic / beta
    t_r = a.allreduces * 2 * math.log2(P) * a.latency_us * 1e-6
    t_h = 0.0
    if a.overlap:
        refresh = a.neighbours * a.latency_us * 1e-6  # one refresh message per neighbour
        if a.async_progress:
            refresh += ghosts * a.refresh_bytes_per_ghost * a.ranks_per_nic / beta
        f_int = max(0.0, n ** (1.0 / 3.0) - 2 * a.delta) ** 3 / n
        t_h = min(refresh, f_int * t_c)
    useful = n * a.t_p_ns * 1e-9
    return useful / (t_c + t_g + t_n + t_r - t_h), ghosts, (t_c, t_g, t_n - t_h, t_r)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    # measured on this machine (docs/performance.md gives the runs)
    ap.add_argument("--t-p-ns", type=float, default=1450.0, help="serial ns per particle-step, 3D bench_box, 1 core (measured, see docs)")
    ap.add_argument("--t-g-ns", type=float, default=1260.0, help="CPU ns per ghost per step (callgrind: 0.87 t_p, see docs)")
    ap.add_argument("--bytes-per-ghost", type=float, default=176.0, help="bytes per ghost per step, 3D (measured)")
    ap.add_argument("--delta", type=float, default=2.6, help="halo depth in particle layers (2 cells of 1.3 dx)")
    ap.add_argument("--messages-per-neighbour", type=float, default=4.0, help="sends per neighbour per step (measured)")
    ap.add_argument("--allreduces", type=float, default=8.0, help="collectives per step (measured: 6 allreduce, 2 allgather)")
    ap.add_argument("--imbalance", type=float, default=1.03, help="heaviest rank / mean (partition, measured trend)")
    # assumed network (a model input, not a measurement)
    ap.add_argument("--latency-us", type=float, default=1.5, help="ASSUMED per-message latency (InfiniBand: 1-2 us)")
    ap.add_argument("--gbit", type=float, default=100.0, help="ASSUMED link bandwidth, Gbit/s (100 Gb/s InfiniBand)")
    ap.add_argument("--ranks-per-nic", type=float, default=32.0, help="ASSUMED ranks sharing one link (32-core nodes, "
                    "every halo byte through the NIC: pessimistic, neighbours on the same node use shared memory)")
    ap.add_argument("--refresh-bytes-per-ghost", type=float, default=64.0,
                    help="bytes per ghost of one refresh, 3D (positions, velocities, densities, pressures)")
    ap.add_argument("--no-overlap", dest="overlap", action="store_false",
                    help="nothing hidden (VARSPH_HALO_OVERLAP=off; the projection before the overlap)")
    ap.add_argument("--async-progress", action="store_true", help="ASSUMED: the network moves rendezvous messages "
                    "while the ranks compute, so the refresh's bytes hide behind the interior sweep too")
    ap.add_argument("--neighbours", type=int, default=26)
    ap.add_argument("--ranks", type=int, default=1000)
    ap.add_argument("--total", type=float, default=1e9, help="particles of the cluster case")
    ap.add_argument("--target", type=float, default=0.8)
    a = ap.parse_args()
    P = a.ranks
    print("inputs: t_p %.0f ns, t_g %.0f ns, %.0f B/ghost/step, delta %.1f, %.1f sends/neighbour/step, %.0f "
          "allreduces/step, imbalance %.3f" % (a.t_p_ns, a.t_g_ns, a.bytes_per_ghost, a.delta,
                                               a.messages_per_neighbour, a.allreduces, a.imbalance))
    print("ASSUMED network: latency %.1f us, %.0f Gb/s, %.0f ranks per link; %d ranks" % (
        a.latency_us, a.gbit, a.ranks_per_nic, P))
    print("overlap: %s" % ("off" if not a.overlap else "refresh latency and bytes hidden (async progress assumed)"
                           if a.async_progress else "refresh latency hidden (bytes move in the wait)"))
    print("%12s %10s %8s %12s %10s %10s %10s %10s" % ("n/rank", "ghosts", "g/n", "halo_MB/step", "compute_s",
                                                     "ghostCPU_s", "network_s", "E"))
    for n in [1e3, 3e3, 1e4, 3e4, 1e5, 3e5, 1e6, 3e6, 1e7]:
        e, g, (tc, tg, tn, tr) = efficiency(n, a, P)
        print("%12.0f %10.0f %8.3f %12.2f %10.4f %10.4f %10.5f %10.3f" % (
            n, g, g / n, g * a.bytes_per_ghost / 1e6, tc, tg, tn + tr, e))
    # smallest n with E >= target (E grows with n)
    lo, hi = 1.0, 1e12
    if efficiency(hi, a, P)[0] < a.target:
        print("efficiency %.2f is not reached at any size (limit 1 / imbalance = %.3f)" % (a.target, 1 / a.imbalance))
        return
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        if efficiency(mid, a, P)[0] >= a.target:
            hi = mid
        else:
            lo = mid
    n_case = a.total / P
    e_case = efficiency(n_case, a, P)[0]
    print("E >= %.2f from n = %.3g particles per rank; %.3g particles on %d ranks = %.3g per rank: E = %.3f" % (
        a.target, hi, a.total, P, n_case, e_case))


if __name__ == "__main__":
    main()
