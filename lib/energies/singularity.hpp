// Evaluation of the I4 / I6 terms of an energy under the chosen singularity mode (paper Sec. 4.2):
//   none      -> the raw closed form tr(S D) (singular where alpha -> 0: the baseline that shows why fixes exist)
//   mollifier -> the smootherstep blend to the proxy (Eq. 33), per term, on alpha or its scale-free form
//   barrier   -> raw terms plus one aberration barrier kappa b(alpha) per element (Eq. 34)
// alpha and its derivatives are computed once per element and shared by all terms.
#pragma once

#include "energies/material.hpp"

namespace aries::energies {

template <int R, int C>
class StretchTerms {
 public:
  static constexpr int N = R * C;
  StretchTerms(const kernels::RootContext<R, C> &ctx, const SingularityParams &sp) : ctx_(ctx), sp_(sp) {
    // alpha's derivatives are only read inside the mollifier's blend band or the barrier's support.
    // In mollifier mode alpha_ is the band's coordinate (-mollifier_measure: alpha or its scale-free form).
    const double a = ctx.rd.root.alpha;
    if (sp_.mode == SingularityMode::Mollifier) {
      const double m = kernels::mollifierCoordinate<R, C>(ctx.F, a, sp_.mollifier);
      if (kernels::inMollifierBand(m, sp_.mollifier))
        alpha_ = kernels::mollifierCoordinate<R, C>(ctx_, sp_.mollifier);
      else
        alpha_.value = m;
    } else if (sp_.mode == SingularityMode::Barrier && a > 0.0 && a < sp_.barrier.eps) {
      alpha_ = kernels::alphaMeasure(ctx_);
    } else {
      alpha_.value = a;
    }
  }

  // tr(S D) (I4 for D = aa^T, I6 for the cross tensor) under the mode.
  kernels::Derivs<N> operator()(const Mat<C, C> &D) const {
    if (sp_.mode == SingularityMode::Mollifier) return kernels::mollifiedStretch<R, C>(ctx_, D, alpha_, sp_.mollifier);
    return kernels::stretchInvariant<R, C>(ctx_, D);
  }

  // kappa b(alpha) in barrier mode, zero otherwise.
  kernels::Derivs<N> barrier() const {
    if (sp_.mode != SingularityMode::Barrier) return {};
    return kernels::aberrationBarrier<N>(alpha_, sp_.barrier, ctx_.order).scale(sp_.barrierStiffness);
  }

 private:
  const kernels::RootContext<R, C> &ctx_;
  const SingularityParams &sp_;
  kernels::Derivs<N> alpha_;
};

}  // namespace aries::energies
