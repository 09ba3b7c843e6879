// Peer benchmark: Pinocchio's generic rigid-body algorithms on a URDF, timed the way
// `robid bench` times robid's compiled models (robots/src/cli/bench.rs): the median over
// 31 batches of about a millisecond each, in nanoseconds per call, with a baseline of
// n x (sin + cos) through the C library (glibc libm) measured in the same process.
//
// Optional and never run by CI: robots/benches/peers/run.sh installs Pinocchio from PyPI
// in a virtual environment under /tmp, compiles this file against the wheels' headers and
// shared libraries, and compares the figures with `robid bench --json` run back to back.
// docs/performance.md#measured-in-the-same-run explains what each figure computes.
//
// Usage: pinocchio_bench URDF LABEL [JOINT_TO_LOCK ...]
//   The listed joints are locked at their neutral value (pinocchio::buildReducedModel):
//   the Panda's two finger joints, so that the model is robid's 7-joint arm.
// Prints one JSON line: {"robot": LABEL, "variant": ..., "nq": n, "programs": {...},
//   "baseline_trig_ns": n x (sin + cos) at the random states, "baseline_trig6_ns":
//   6 x (sin + cos) at the values robid's own baseline uses, "baseline_sincos6_ns": the
//   same through 6 x sincos, "check_residual": max |rnea - (M a + nle)| at one state}.
//
// Build (run.sh does this), PREFIX = <venv>/lib/python3.X/site-packages/cmeel.prefix:
//   g++ -std=c++17 -O3 -DNDEBUG pinocchio_bench.cpp -I$PREFIX/include \
//     -I$PREFIX/include/eigen3 -I$PREFIX/include/urdfdom_headers \
//     -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 \
//     -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12 \
//     -L$PREFIX/lib -Wl,-rpath,$PREFIX/lib -lpinocchio_parsers -lpinocchio_default \
//     -lurdfdom_model -lconsole_bridge -o pinocchio_bench
// Without PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION the algorithms are instantiated from the
// headers in this file, with this compiler's flags (the usual way Pinocchio is used from
// C++); with it defined they are the wheel's precompiled instances in libpinocchio_default.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "pinocchio/algorithm/crba.hpp"
#include "pinocchio/algorithm/joint-configuration.hpp"
#include "pinocchio/algorithm/model.hpp"
#include "pinocchio/algorithm/rnea.hpp"
#include "pinocchio/multibody.hpp"
#include "pinocchio/parsers/urdf.hpp"

namespace
{

  // Tells the compiler that `p` is read and written by someone it cannot see: the work
  // that produced *p happens, and nothing is hoisted out of the timing loop.
  template<typename T>
  inline void escape(T * p)
  {
    asm volatile("" : : "g"(p) : "memory");
  }

  inline void clobber()
  {
    asm volatile("" : : : "memory");
  }

  // Median time per call of `f` over 31 batches of about a millisecond each (the
  // calibration of robots/src/cli/bench.rs: double the batch until it takes > 1 ms).
  template<typename F>
  double median_ns(F && f)
  {
    using clock = std::chrono::steady_clock;
    std::size_t batch = 1;
    for (;;)
    {
      const auto t = clock::now();
      for (std::size_t i = 0; i < batch; ++i)
        f();
      const double s = std::chrono::duration<double>(clock::now() - t).count();
      if (s > 1e-3 || batch >= (std::size_t(1) << 24))
        break;
      batch *= 2;
    }
    std::vector<double> samples;
    for (int k = 0; k < 31; ++k)
    {
      const auto t = clock::now();
      for (std::size_t i = 0; i < batch; ++i)
        f();
      const double s = std::chrono::duration<double>(clock::now() - t).count();
      samples.push_back(s * 1e9 / double(batch));
    }
    std::sort(samples.begin(), samples.end());
    return samples[samples.size() / 2];
  }

  // n x (sin + cos) through the C library's sin and cos (glibc libm), on the states of
  // `qs` taken in turn, like the algorithms below.
  double trig_ns(const std::vector<std::vector<double>> & qs)
  {
    const std::size_t n = qs[0].size();
    std::vector<double> acc(2 * n);
    std::size_t s = 0;
    return median_ns([&] {
      const double * q = qs[s].data();
      escape(q);
      for (std::size_t j = 0; j < n; ++j)
      {
        acc[2 * j] = ::sin(q[j]);
        acc[2 * j + 1] = ::cos(q[j]);
      }
      escape(acc.data());
      s = (s + 1) % qs.size();
    });
  }

  // The same through glibc's sincos (one call a joint): what compilers emit for
  // sin(x) and cos(x) of the same x when they may (LLVM does for Rust's f64::sin and
  // f64::cos; g++ -O3 without -ffast-math does not).
  double sincos_ns(const std::vector<std::vector<double>> & qs)
  {
    const std::size_t n = qs[0].size();
    std::vector<double> acc(2 * n);
    std::size_t s = 0;
    return median_ns([&] {
      const double * q = qs[s].data();
      escape(q);
      for (std::size_t j = 0; j < n; ++j)
        ::sincos(q[j], &acc[2 * j], &acc[2 * j + 1]);
      escape(acc.data());
      s = (s + 1) % qs.size();
    });
  }

} // namespace

int main(int argc, char ** argv)
{
  if (argc < 3)
  {
    std::fprintf(stderr, "usage: %s URDF LABEL [JOINT_TO_LOCK ...]\n", argv[0]);
    return 2;
  }
  const std::string urdf = argv[1];
  const std::string label = argv[2];

  pinocchio::Model full;
  pinocchio::urdf::buildModel(urdf, full);
  pinocchio::Model model;
  if (argc > 3)
  {
    std::vector<pinocchio::JointIndex> locked;
    for (int i = 3; i < argc; ++i)
    {
      if (!full.existJointName(argv[i]))
      {
        std::fprintf(stderr, "no joint `%s` in %s\n", argv[i], urdf.c_str());
        return 2;
      }
      locked.push_back(full.getJointId(argv[i]));
    }
    model = pinocchio::buildReducedModel(full, locked, pinocchio::neutral(full));
  }
  else
    model = full;
  pinocchio::Data data(model);
  const int n = model.nv;
  if (model.nq != model.nv)
  {
    std::fprintf(stderr, "nq = %d != nv = %d: only revolute/prismatic chains\n", model.nq, n);
    return 2;
  }

  // A pool of random states within the joint limits (fixed seed), taken in turn by every
  // timed call: states change from call to call, as they do along a trajectory.
  const int pool = 64;
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Eigen::VectorXd> qs, vs, as;
  std::vector<std::vector<double>> qraw;
  for (int k = 0; k < pool; ++k)
  {
    Eigen::VectorXd q(n), v(n), a(n);
    for (int j = 0; j < n; ++j)
    {
      const double lo = std::max(model.lowerPositionLimit[j], -M_PI);
      const double hi = std::min(model.upperPositionLimit[j], M_PI);
      q[j] = lo + (hi - lo) * 0.5 * (unit(rng) + 1.0);
      v[j] = 2.0 * unit(rng);
      a[j] = 5.0 * unit(rng);
    }
    qs.push_back(q);
    vs.push_back(v);
    as.push_back(a);
    qraw.emplace_back(q.data(), q.data() + n);
  }

  std::size_t s = 0;
  auto next = [&] { s = (s + 1) % pool; };

  const double trig = trig_ns(qraw);
  // robid's own baseline: 6 x (sin + cos) at q_j = sin(0.3 + 0.17 j), one fixed state.
  std::vector<std::vector<double>> robid_q(1);
  for (int j = 0; j < 6; ++j)
    robid_q[0].push_back(std::sin(0.3 + 0.17 * j));
  const double trig6 = trig_ns(robid_q);
  const double sincos6 = sincos_ns(robid_q);

  // Inverse dynamics: tau = M(q) a + C(q, v) v + g(q) (rigid bodies, armature included).
  const double rnea = median_ns([&] {
    escape(qs[s].data());
    pinocchio::rnea(model, data, qs[s], vs[s], as[s]);
    escape(data.tau.data());
    next();
  });
  // Mass matrix, upper triangle only (Pinocchio's convention: data.M's strictly lower part
  // is left as it was).
  const double crba = median_ns([&] {
    escape(qs[s].data());
    pinocchio::crba(model, data, qs[s]);
    escape(data.M.data());
    next();
  });
  // The same, made symmetric (robid's mass matrix fills all n x n entries).
  const double crba_full = median_ns([&] {
    escape(qs[s].data());
    pinocchio::crba(model, data, qs[s]);
    data.M.triangularView<Eigen::StrictlyLower>() =
      data.M.transpose().triangularView<Eigen::StrictlyLower>();
    escape(data.M.data());
    next();
  });
  // Gravity torques g(q).
  const double gravity = median_ns([&] {
    escape(qs[s].data());
    pinocchio::computeGeneralizedGravity(model, data, qs[s]);
    escape(data.g.data());
    next();
  });
  // Nonlinear effects C(q, v) v + g(q): the RNEA with a = 0 (gravity costs nothing more in
  // the RNEA: it is the base's acceleration). robid's `coriolis` is C(q, qd) qd alone.
  const double nle = median_ns([&] {
    escape(qs[s].data());
    pinocchio::nonLinearEffects(model, data, qs[s], vs[s]);
    escape(data.nle.data());
    next();
  });
  clobber();

  // Consistency of what was timed: rnea(q, v, a) = M(q) a + nle(q, v) at one state, with
  // M symmetrised from crba's upper triangle (a wrong build or ABI shows here).
  pinocchio::rnea(model, data, qs[0], vs[0], as[0]);
  const Eigen::VectorXd tau = data.tau;
  pinocchio::crba(model, data, qs[0]);
  const Eigen::MatrixXd m = data.M.selfadjointView<Eigen::Upper>();
  pinocchio::nonLinearEffects(model, data, qs[0], vs[0]);
  const double residual = (tau - m * as[0] - data.nle).cwiseAbs().maxCoeff();
  if (!(residual < 1e-9 * (1.0 + tau.cwiseAbs().maxCoeff())))
  {
    std::fprintf(stderr, "rnea != M a + nle: residual %g\n", residual);
    return 1;
  }

#ifdef PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION
  const char * instances = "library";
#else
  const char * instances = "headers";
#endif
#ifdef PEER_TARGET // a -march given by hand (-DPEER_TARGET='"native"'), if any
  const char * target = PEER_TARGET;
#else
  const char * target = "default";
#endif
  std::printf(
    "{\"robot\":\"%s\",\"variant\":\"%s-%s\",\"nq\":%d,\"programs\":{\"rnea\":%.3f,"
    "\"crba\":%.3f,\"crba_symmetric\":%.3f,\"computeGeneralizedGravity\":%.3f,"
    "\"nonLinearEffects\":%.3f},\"baseline_trig_ns\":%.3f,\"baseline_trig6_ns\":%.3f,"
    "\"baseline_sincos6_ns\":%.3f,\"check_residual\":%.3g}\n",
    label.c_str(), target, instances, n, rnea, crba, crba_full, gravity, nle, trig, trig6,
    sincos6, residual);
  return 0;
}
