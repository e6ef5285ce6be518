// wedge_similarity_bem: the reference for Wagner's wedge case (issue 30 point 6; docs/validation.md section 18).
// A symmetric wedge of deadrise beta enters still, weightless, inviscid, incompressible water at constant speed V = 1;
// the flow is computed in time by a fully nonlinear potential-flow boundary-element method until it is self-similar,
// an independent check of the similarity solution of Dobrovol'skaya (1969) tabulated by Zhao & Faltinsen (1993)
// (tests/data/zhao_faltinsen1993_wedge_similarity.csv). Method (textbook; e.g. Zhao & Faltinsen 1993, section 2):
//  * Green's third identity c(P) phi(P) = int [phi d(ln r)/dn - (d phi/dn) ln r] dS on the boundary (outward normal n),
//    linear elements collocated at the nodes, the symmetry plane x = 0 by images, c(P) from the constant-phi identity;
//  * boundary: the wedge face (d phi/dn = V . n = -cos(beta)), the free surface (phi given), a far arc of radius
//    150 h (phi = 0);
//  * free surface Lagrangian (mixed Eulerian-Lagrangian): dX/dt = grad phi, d phi/dt = |grad phi|^2 / 2 (p = 0, no
//    gravity), RK4, regridded every step (geometric spacing from the contact point), 5-point smoothing
//    (Longuet-Higgins & Cokelet 1976); the contact point moves with the velocity that satisfies both normal
//    conditions there; the jet along the face is cut where the free surface folds back within --cut degrees of the
//    face (as Zhao & Faltinsen do);
//  * start: the apex 1 below a flat surface, impulsively set in motion; the pressure on the face from Bernoulli with
//    the self-similar d phi/dt = (phi - x . grad phi) / t ('ss', valid once self-similar) and, as a check, from a
//    time difference at body-fixed points ('td').
// Printed against the penetration h: the contact point, F / (rho V^3 t) (= F / h in these units, both faces),
// Cp_max = p_max / (rho V^2 / 2) and z_max / (V t) (the height of the largest face pressure above the still water).
//   wedge_similarity_bem [--beta 30] [--h-end 12] [--cut 15] [--eps 0.02] [--grow 1.1] [--cfl 0.25] [--profile FILE]
// Bad arguments: exit 2 naming the flag. Measured (docs/validation.md section 18; ~10 min on one loaded core): at 30 deg
// the defaults give, at h = 7.5-9.3 (means over the steps), F/(rho V^3 t) 13.60-13.77 (14.28 with p >= 0 at 9.3),
// Cp_max 6.91-6.92, z_max/(V t) 0.417-0.418. Not working: beta 20 deg (the cut criterion eats the wetted part).
#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>
using V2 = Eigen::Vector2d;
static double TB, SB, CB; // tan, sin, cos of the deadrise
static const double PI = 3.14159265358979323846;
static double gx[16], gw[16];
static void gauss_init() {
  int n = 16;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(PI * (i + 0.75) / (n + 0.5));
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k) { double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k; p0 = p1; p1 = p2; }
      double dp = n * (x * p1 - p0) / (x * x - 1);
      double dx = p1 / dp; x -= dx;
      if (std::fabs(dx) < 1e-15) break;
    }
    double p0 = 1, p1 = x;
    for (int k = 2; k <= n; ++k) { double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k; p0 = p1; p1 = p2; }
    double dp = n * (x * p1 - p0) / (x * x - 1);
    gx[i] = x; gw[i] = 2 / ((1 - x * x) * dp * dp);
  }
}
// integrals over the straight element Q0->Q1 (outward normal n) of N_a, N_b times ln r and d(ln r)/dn_Q for the point P
static void elem_int(const V2& P, const V2& Q0, const V2& Q1, const V2& n, double& Ga, double& Gb, double& Ha, double& Hb) {
  V2 d = Q1 - Q0; double L = d.norm();
  Ga = Gb = Ha = Hb = 0;
  double e0 = (P - Q0).norm(), e1 = (P - Q1).norm();
  if (e0 < 1e-12 * L) { Ga = 0.5 * L * std::log(L) - 0.75 * L; Gb = 0.5 * L * std::log(L) - 0.25 * L; return; }
  if (e1 < 1e-12 * L) { Ga = 0.5 * L * std::log(L) - 0.25 * L; Gb = 0.5 * L * std::log(L) - 0.75 * L; return; }
  double dist = std::min(e0, e1);
  double s = ((P - Q0).dot(d)) / (L * L);
  if (s > 0 && s < 1) dist = std::min(dist, std::fabs((P - Q0).dot(n)));
  int m = (int)std::ceil(3.0 * L / std::max(dist, 1e-300));
  if (m < 1) m = 1; if (m > 200) m = 200;
  for (int k = 0; k < m; ++k) {
    double a = (double)k / m, b = (double)(k + 1) / m;
    for (int g = 0; g < 16; ++g) {
      double u = 0.5 * (a + b) + 0.5 * (b - a) * gx[g], w = 0.5 * (b - a) * gw[g] * L;
      V2 Q = Q0 + u * d; V2 r = Q - P; double r2 = r.squaredNorm();
      double lr = 0.5 * std::log(r2), dn = r.dot(n) / r2;
      Ga += (1 - u) * lr * w; Gb += u * lr * w; Ha += (1 - u) * dn * w; Hb += u * dn * w;
    }
  }
}
struct FS { std::vector<V2> p; std::vector<double> phi; };
// cubic Hermite (Catmull-Rom on chord length) resampling of a polyline with a scalar
static void resample(const std::vector<double>& s, const std::vector<double>& f, const std::vector<double>& snew, std::vector<double>& out) {
  int n = (int)s.size(); out.resize(snew.size());
  std::vector<double> m(n);
  for (int i = 0; i < n; ++i) {
    if (i == 0) m[i] = (f[1] - f[0]) / (s[1] - s[0]);
    else if (i == n - 1) m[i] = (f[n - 1] - f[n - 2]) / (s[n - 1] - s[n - 2]);
    else { double h0 = s[i] - s[i - 1], h1 = s[i + 1] - s[i];
      m[i] = (h0 * h0 * (f[i + 1] - f[i]) + h1 * h1 * (f[i] - f[i - 1])) / (h0 * h1 * (h0 + h1)); }
  }
  int j = 0;
  for (size_t k = 0; k < snew.size(); ++k) {
    double x = snew[k];
    while (j < n - 2 && s[j + 1] < x) ++j;
    double h = s[j + 1] - s[j], t = (x - s[j]) / h; t = std::max(0.0, std::min(1.0, t));
    double h00 = 2 * t * t * t - 3 * t * t + 1, h10 = t * t * t - 2 * t * t + t, h01 = -2 * t * t * t + 3 * t * t, h11 = t * t * t - t * t;
    out[k] = h00 * f[j] + h10 * h * m[j] + h01 * f[j + 1] + h11 * h * m[j + 1];
  }
}
struct Sol { std::vector<V2> face; std::vector<double> phface; std::vector<V2> ufs; V2 ucorner; double xc; };
static double G_EPS = 0.02, G_GROW = 1.1, RFAC = 60.0; static int NARC = 48;
// solve the BVP for penetration h with free surface fs; returns face nodes, face phi and free-surface velocities
static Sol solve(double h, const FS& fs) {
  Sol S;
  V2 A(0, -h), C = fs.p[0];
  double Lf = (C - A).norm(); S.xc = C.x();
  // face nodes from C down to A, geometric
  std::vector<double> sig; { double ds = std::max((fs.p[1] - fs.p[0]).norm(), 1e-3 * Lf), acc = 0; sig.push_back(0);
    while (acc + ds < Lf - 0.5 * ds) { acc += ds; sig.push_back(acc); ds = std::min(ds * G_GROW, 0.04 * Lf); }
    sig.push_back(Lf); }
  int Nf = (int)sig.size();
  std::vector<V2> nodes; // global: face A..C, fs 1..end, arc
  for (int i = Nf - 1; i >= 0; --i) nodes.push_back(C + (A - C) * (sig[i] / Lf));
  int Ns = (int)fs.p.size();
  for (int k = 1; k < Ns; ++k) nodes.push_back(fs.p[k]);
  double R = fs.p[Ns - 1].x();
  for (int k = 0; k < NARC; ++k) { double th = -0.002 - (PI / 2 - 0.002) * k / (NARC - 1); nodes.push_back(V2(R * std::cos(th), R * std::sin(th))); }
  int N = (int)nodes.size(); int iC = Nf - 1, iFend = Nf - 1 + Ns - 1, iA0 = iFend + 1;
  // elements
  struct E { int a, b, type; }; std::vector<E> el; // type 0 face, 1 fs, 2 arc
  for (int i = 0; i < Nf - 1; ++i) el.push_back({i, i + 1, 0});
  for (int i = iC; i < iFend; ++i) el.push_back({i, i + 1, 1});
  for (int i = iA0; i < N - 1; ++i) el.push_back({i, i + 1, 2});
  // unknown index: face nodes 0..Nf-2 -> phi; fs nodes iC..iFend -> phin; arc nodes -> phin
  int NU = N; // unknown k = node index (face nodes < iC: phi; others: phin) ; corner iC: phin_fs
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(N, NU); Eigen::VectorXd rhs = Eigen::VectorXd::Zero(N);
  std::vector<double> phik(N, 0.0); // known phi at Dirichlet nodes
  for (int k = 0; k < Ns; ++k) phik[iC + k] = fs.phi[k];
  double phin_face = -CB;
  for (int i = 0; i < N; ++i) {
    const V2& P = nodes[i]; double ci = 0;
    for (const E& e : el) {
      V2 Q0 = nodes[e.a], Q1 = nodes[e.b]; V2 d = Q1 - Q0; V2 n(-d.y(), d.x()); n /= n.norm();
      double Ga, Gb, Ha, Hb, ga, gb, ha, hb;
      elem_int(P, Q0, Q1, n, Ga, Gb, Ha, Hb);
      V2 Q0m(-Q0.x(), Q0.y()), Q1m(-Q1.x(), Q1.y()), nm(-n.x(), n.y());
      elem_int(P, Q0m, Q1m, nm, ga, gb, ha, hb);
      Ga += ga; Gb += gb; Ha += ha; Hb += hb;
      ci += Ha + Hb;
      // - sum H phi
      int nd[2] = {e.a, e.b}; double H[2] = {Ha, Hb}, G[2] = {Ga, Gb};
      for (int q = 0; q < 2; ++q) {
        int j = nd[q];
        if (j < iC) M(i, j) -= H[q]; else rhs(i) += H[q] * phik[j];
        if (e.type == 0) rhs(i) -= G[q] * phin_face; else M(i, j) += G[q];
      }
    }
    if (i < iC) M(i, i) += ci; else rhs(i) -= ci * phik[i];
  }
  Eigen::VectorXd x = M.partialPivLu().solve(rhs);
  S.face.resize(Nf); S.phface.resize(Nf);
  for (int i = 0; i < Nf; ++i) { S.face[i] = nodes[i]; S.phface[i] = i < iC ? x(i) : phik[iC]; }
  // free-surface velocities
  S.ufs.resize(Ns);
  std::vector<double> s(Ns, 0.0); for (int k = 1; k < Ns; ++k) s[k] = s[k - 1] + (fs.p[k] - fs.p[k - 1]).norm();
  for (int k = 0; k < Ns; ++k) {
    double phs; V2 t;
    if (k == 0) { phs = (fs.phi[1] - fs.phi[0]) / (s[1] - s[0]); t = (fs.p[1] - fs.p[0]).normalized(); }
    else if (k == Ns - 1) { phs = (fs.phi[k] - fs.phi[k - 1]) / (s[k] - s[k - 1]); t = (fs.p[k] - fs.p[k - 1]).normalized(); }
    else { double h0 = s[k] - s[k - 1], h1 = s[k + 1] - s[k];
      phs = (h0 * h0 * (fs.phi[k + 1] - fs.phi[k]) + h1 * h1 * (fs.phi[k] - fs.phi[k - 1])) / (h0 * h1 * (h0 + h1));
      t = (fs.p[k + 1] - fs.p[k - 1]).normalized(); }
    V2 n(-t.y(), t.x());
    S.ufs[k] = phs * t + x(iC + k) * n;
  }
  { // corner: two normal conditions
    V2 nf(-SB, CB); V2 t = (fs.p[1] - fs.p[0]).normalized(); V2 ns(-t.y(), t.x());
    Eigen::Matrix2d A2; A2 << nf.x(), nf.y(), ns.x(), ns.y(); Eigen::Vector2d b2(-CB, x(iC));
    Eigen::Vector2d u = A2.partialPivLu().solve(b2); S.ucorner = V2(u(0), u(1));
    S.ufs[0] = S.ucorner;
  }
  return S;
}
// regrid the free surface: geometric spacing from the corner, growing to the far end at R
static void regrid(FS& fs, double R) {
  int n = (int)fs.p.size();
  std::vector<double> s(n, 0.0); for (int k = 1; k < n; ++k) s[k] = s[k - 1] + (fs.p[k] - fs.p[k - 1]).norm();
  double xc = fs.p[0].x(); double d0 = G_EPS * xc;
  if (!(d0 > 0) || !(s[n - 1] > 0)) { std::fprintf(stderr, "regrid: bad geometry xc %g len %g\n", xc, s[n - 1]); std::exit(3); }
  std::vector<double> sn; double acc = 0, ds = d0; sn.push_back(0);
  double Stot = s[n - 1];
  while (acc + ds < Stot - 0.5 * ds) { acc += ds; sn.push_back(acc); ds = std::min(ds * G_GROW, 0.03 * R); }
  sn.push_back(Stot);
  std::vector<double> xs(n), ys(n), xo, yo, po;
  for (int k = 0; k < n; ++k) { xs[k] = fs.p[k].x(); ys[k] = fs.p[k].y(); }
  resample(s, xs, sn, xo); resample(s, ys, sn, yo); resample(s, fs.phi, sn, po);
  fs.p.resize(sn.size()); fs.phi = po;
  for (size_t k = 0; k < sn.size(); ++k) fs.p[k] = V2(xo[k], yo[k]);
  (void)R;
}
static void project_corner(FS& fs, double h) { // onto the face line y = -h + x tan(beta)
  V2 A(0, -h), t(CB, SB); V2 q = fs.p[0] - A; fs.p[0] = A + q.dot(t) * t;
}
static double arg_num(int argc, char** argv, int& i, double lo, double hi) {
  const char* flag = argv[i];
  if (i + 1 >= argc) { std::fprintf(stderr, "wedge_similarity_bem: %s: expected a number\n", flag); std::exit(2); }
  char* end = nullptr; double v = std::strtod(argv[++i], &end);
  if (end == argv[i] || *end != 0 || !(v >= lo && v <= hi)) {
    std::fprintf(stderr, "wedge_similarity_bem: %s: expected a number in [%g, %g], got '%s'\n", flag, lo, hi, argv[i]); std::exit(2); }
  return v;
}
int main(int argc, char** argv) {
  double beta_deg = 30, hend = 12, cut_deg = 15, cfl = 0.25; const char* profile = nullptr; int nsmooth = 1;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--beta") beta_deg = arg_num(argc, argv, i, 2, 60);
    else if (a == "--h-end") hend = arg_num(argc, argv, i, 1.01, 1000);
    else if (a == "--cut") cut_deg = arg_num(argc, argv, i, 1, 60);
    else if (a == "--eps") G_EPS = arg_num(argc, argv, i, 1e-4, 0.2);
    else if (a == "--grow") G_GROW = arg_num(argc, argv, i, 1.001, 1.5);
    else if (a == "--cfl") cfl = arg_num(argc, argv, i, 1e-3, 1);
    else if (a == "--smooth") nsmooth = (int)arg_num(argc, argv, i, 0, 1000);
    else if (a == "--profile") { if (i + 1 >= argc) { std::fprintf(stderr, "wedge_similarity_bem: --profile: expected a file name\n"); return 2; } profile = argv[++i]; }
    else { std::fprintf(stderr, "wedge_similarity_bem: unknown argument '%s' (see the header of bench/bodies/wedge_similarity_bem.cpp)\n", argv[i]); return 2; }
  }
  gauss_init();
  double b = beta_deg * PI / 180; TB = std::tan(b); SB = std::sin(b); CB = std::cos(b);
  double h = 1.0; // initial penetration (length unit)
  FS fs; { double xc = h / TB, R = RFAC * h * 2.5; int n = 200; for (int k = 0; k < n; ++k) { double u = (double)k / (n - 1);
      double x = xc + (R - xc) * (std::exp(6 * u) - 1) / (std::exp(6.0) - 1); fs.p.push_back(V2(x, 0)); fs.phi.push_back(0); } }
  regrid(fs, fs.p.back().x());
  double t = 0; int step = 0; double next_print = 1.25; int acc_n = 0; double acc_F = 0, acc_Fp = 0, acc_F2 = 0, acc_cp = 0, acc_z = 0, acc_xc = 0;
  std::vector<double> prev_sig, prev_phi; double prev_h = -1;
  while (h < hend) {
    // jet cut
    { V2 tf(-CB, -SB); int j = 0; int n = (int)fs.p.size();
      while (j < n - 2) { V2 te = (fs.p[j + 1] - fs.p[j]).normalized(); double ang = std::acos(std::max(-1.0, std::min(1.0, te.dot(tf)))) * 180 / PI;
        if (ang > cut_deg) break; ++j; }
      if (j > 0) { fs.p.erase(fs.p.begin(), fs.p.begin() + j); fs.phi.erase(fs.phi.begin(), fs.phi.begin() + j); project_corner(fs, h); } }
    double R = RFAC * 2.5 * h; fs.p.back() = V2(R, 0); fs.phi.back() = 0; // far end grows with h (flat, phi = 0)
    regrid(fs, R);
    if (nsmooth > 0 && step % nsmooth == 0) { int n = (int)fs.p.size(); FS o = fs;
      for (int k = 2; k < n - 2; ++k) { fs.p[k] = (-o.p[k - 2] + 4.0 * o.p[k - 1] + 10.0 * o.p[k] + 4.0 * o.p[k + 1] - o.p[k + 2]) / 16.0;
        fs.phi[k] = (-o.phi[k - 2] + 4 * o.phi[k - 1] + 10 * o.phi[k] + 4 * o.phi[k + 1] - o.phi[k + 2]) / 16.0; }
      fs.p[1] = 0.25 * o.p[0] + 0.5 * o.p[1] + 0.25 * o.p[2]; fs.phi[1] = 0.25 * o.phi[0] + 0.5 * o.phi[1] + 0.25 * o.phi[2]; }
    Sol S0 = solve(h, fs);
    double umax = 0; for (auto& u : S0.ufs) umax = std::max(umax, u.norm());
    double dmin = (fs.p[1] - fs.p[0]).norm(); double dt = cfl * dmin / std::max(umax, 1.0);
    // RK4
    FS f0 = fs; std::vector<V2> kp[4]; std::vector<double> kf[4];
    auto deriv = [&](const Sol& S, std::vector<V2>& dp, std::vector<double>& df) { int n = (int)S.ufs.size(); dp.resize(n); df.resize(n);
      for (int k = 0; k < n; ++k) { dp[k] = S.ufs[k]; df[k] = 0.5 * S.ufs[k].squaredNorm(); } dp[n - 1] = V2(0, 0); df[n - 1] = 0; };
    deriv(S0, kp[0], kf[0]);
    double cw[4] = {0, 0.5, 0.5, 1};
    for (int st = 1; st < 4; ++st) { FS f = f0; for (size_t k = 0; k < f.p.size(); ++k) { f.p[k] += cw[st] * dt * kp[st - 1][k]; f.phi[k] += cw[st] * dt * kf[st - 1][k]; }
      project_corner(f, h + cw[st] * dt); Sol S = solve(h + cw[st] * dt, f); deriv(S, kp[st], kf[st]); }
    for (size_t k = 0; k < fs.p.size(); ++k) { fs.p[k] += dt / 6 * (kp[0][k] + 2 * kp[1][k] + 2 * kp[2][k] + kp[3][k]); fs.phi[k] += dt / 6 * (kf[0][k] + 2 * kf[1][k] + 2 * kf[2][k] + kf[3][k]); }
    // diagnostics at the old time level from S0 (self-similar pressure) and a time difference on body-fixed points
    {
      int Nf = (int)S0.face.size(); std::vector<double> sig(Nf), p(Nf), p2(Nf, NAN);
      for (int i = 0; i < Nf; ++i) sig[i] = (S0.face[i] - V2(0, -h)).norm();
      double F = 0, F2 = 0, pmax = -1e9, ypmax = 0; bool have2 = prev_h > 0;
      std::vector<double> phprev; if (have2) resample(prev_sig, prev_phi, sig, phprev);
      for (int i = 0; i < Nf; ++i) {
        double phs; if (i == 0) phs = (S0.phface[1] - S0.phface[0]) / (sig[1] - sig[0]); else if (i == Nf - 1) phs = (S0.phface[i] - S0.phface[i - 1]) / (sig[i] - sig[i - 1]);
        else { double h0 = sig[i] - sig[i - 1], h1 = sig[i + 1] - sig[i]; phs = (h0 * h0 * (S0.phface[i + 1] - S0.phface[i]) + h1 * h1 * (S0.phface[i] - S0.phface[i - 1])) / (h0 * h1 * (h0 + h1)); }
        V2 g = phs * V2(CB, SB) + (-CB) * V2(-SB, CB);
        double pt = (S0.phface[i] - S0.face[i].dot(g)) / h; // self-similar phi_t (origin at the still-water point of the axis)
        p[i] = -(pt + 0.5 * g.squaredNorm());
        if (have2) { double dphidt = (S0.phface[i] - phprev[i]) / (h - prev_h); double pt2 = dphidt + g.y(); p2[i] = -(pt2 + 0.5 * g.squaredNorm()); }
        if (p[i] > pmax) { pmax = p[i]; ypmax = S0.face[i].y(); }
      }
      double Fpos = 0; // the same with the pressure clipped at 0: between the jet root and the cut contact point the
                       // computed pressure dips below 0 (down to Cp -2), an artefact of the cut; the exact one tends to 0
      for (int i = 0; i + 1 < Nf; ++i) { double dx = std::fabs(S0.face[i + 1].x() - S0.face[i].x()); F += (p[i] + p[i + 1]) * dx;
        Fpos += (std::max(p[i], 0.0) + std::max(p[i + 1], 0.0)) * dx; if (have2) F2 += (p2[i] + p2[i + 1]) * dx; }
      // means over the steps since the previous line (the jet cuts make the contact point, and so the force, saw-tooth)
      acc_n += 1; acc_F += F / h; acc_Fp += Fpos / h; acc_F2 += have2 ? F2 / h : 0; acc_cp += 2 * pmax; acc_z += ypmax / h; acc_xc += S0.xc / h;
      if (h >= next_print) {
        if (profile) { FILE* fo = std::fopen(profile, "w"); if (!fo) { std::fprintf(stderr, "wedge_similarity_bem: --profile: cannot write %s\n", profile); std::exit(2); }
          std::fprintf(fo, "# h %.4f\nxi_x_over_h,z_over_h,cp_selfsimilar,cp_timedifference\n", h);
          for (int i = 0; i < Nf; ++i) std::fprintf(fo, "%.5f,%.5f,%.5f,%.5f\n", S0.face[i].x() / h, S0.face[i].y() / h, 2 * p[i], 2 * p2[i]); std::fclose(fo); }
        std::printf("h %7.3f steps %6d nfs %4d nface %4d | means over %4d steps: contact x/h %.4f, F/(rho V^3 t) ss %.4f (p >= 0: %.4f) td %.4f, Cp_max %.4f, z_max/(V t) %.4f, F/Wagner %.4f\n",
                    h, step, (int)fs.p.size(), Nf, acc_n, acc_xc / acc_n, acc_F / acc_n, acc_Fp / acc_n, acc_F2 / acc_n, acc_cp / acc_n, acc_z / acc_n,
                    (acc_F / acc_n) / (PI * PI * PI / (4 * TB * TB)));
        std::fflush(stdout);
        next_print *= 1.25; acc_n = 0; acc_F = acc_Fp = acc_F2 = acc_cp = acc_z = acc_xc = 0;
      }
    }
    // keep the body-fixed face phi for the time-difference pressure (one step back)
    { int Nf = (int)S0.face.size(); prev_sig.resize(Nf); prev_phi.resize(Nf); for (int i = 0; i < Nf; ++i) { prev_sig[i] = (S0.face[i] - V2(0, -h)).norm(); prev_phi[i] = S0.phface[i]; }
      // reverse to increasing sigma order for resample (face nodes go A..C: sigma increasing already)
      prev_h = h; }
    project_corner(fs, h + dt);
    h += dt; t += dt; ++step;
  }
  return 0;
}
