#pragma once
/// \file PhaseFunction: a value type dispatching statically over a closed list of phase
/// functions (std::variant + std::visit, in the spirit of pbrt-v4's TaggedPointer dispatch).
///
/// Every alternative P provides
///   static constexpr const char* kName;
///   double eval(const Vec3& wo, const Vec3& wi) const;   // p(wo, wi), ∫ p dω_i = 1
///   double pdf(const Vec3& wo, const Vec3& wi) const;    // solid-angle density of sample()
///   PhaseSample sample(const Vec3& wo, const Vec2& u) const;
/// with wo the propagation direction before scattering and wi the one after (DESIGN.md).
/// Adding a phase function = one class with those members + one entry in Variant below.
#include <cmath>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "shvol/phase/cornette_shanks_phase.h"
#include "shvol/phase/henyey_greenstein_phase.h"
#include "shvol/phase/isotropic_phase.h"
#include "shvol/phase/phase_sample.h"
#include "shvol/phase/rayleigh_phase.h"
#include "shvol/phase/schlick_phase.h"
#include "shvol/phase/sh_sampled_phase.h"
#include "shvol/phase/tabulated_phase.h"
#include "shvol/phase/two_term_hg_phase.h"

namespace shvol {

class PhaseFunction {
  public:
    using Variant = std::variant<IsotropicPhase,                //
                                 HenyeyGreensteinPhase,         //
                                 TwoTermHenyeyGreensteinPhase,  //
                                 RayleighPhase,                 //
                                 SchlickPhase,                  //
                                 CornetteShanksPhase,           //
                                 TabulatedPhase,                //
                                 SHSampledPhase>;

    /// Isotropic by default.
    PhaseFunction() = default;
    PhaseFunction(IsotropicPhase p) : p_(p) {}
    PhaseFunction(HenyeyGreensteinPhase p) : p_(p) {}
    /// Any other alternative of Variant.
    template <typename P,
              typename = std::enable_if_t<std::is_constructible_v<Variant, P> &&
                                          !std::is_same_v<std::decay_t<P>, PhaseFunction>>>
    PhaseFunction(P p) : p_(std::move(p)) {}

    double eval(const Vec3& wo, const Vec3& wi) const {
        return std::visit([&](const auto& p) { return p.eval(wo, wi); }, p_);
    }
    double pdf(const Vec3& wo, const Vec3& wi) const {
        return std::visit([&](const auto& p) { return p.pdf(wo, wi); }, p_);
    }
    /// p at the angle c between wo and wi (the phase functions are rotationally symmetric), with
    /// sin θ from c's complements rather than from μ; for zonal fits (fitZonal).
    double evalAngle(const AngleCosine& c) const {
        return eval(Vec3(0, 0, 1), sphericalDirectionFromCosSin(c.mu, c.sinTheta(), Vec2(1, 0)));
    }
    PhaseSample sample(const Vec3& wo, const Vec2& u) const {
        return std::visit([&](const auto& p) { return p.sample(wo, u); }, p_);
    }
    /// Angles θ (radians) where p is not smooth, for quadrature panels to end at (fitZonal) and
    /// the search of its peak (peakOverIsotropic): a table's nodes, where its piecewise-linear
    /// interpolant has corners, also under an SH sampler (which may evaluate it exactly, and
    /// whose product lobe is fitted to it); none for the others.
    std::vector<double> corners() const {
        if (const auto* sh = std::get_if<SHSampledPhase>(&p_)) return sh->base().corners();
        std::vector<double> theta;
        if (const auto* t = std::get_if<TabulatedPhase>(&p_))
            for (double mu : t->table().nodes()) theta.push_back(std::acos(mu));
        return theta;
    }
    /// kName of the alternative: "isotropic", "hg", "two_term_hg", "rayleigh", "schlick",
    /// "cornette_shanks", "tabulated".
    std::string name() const {
        return std::visit(
            [](const auto& p) { return std::string(std::decay_t<decltype(p)>::kName); }, p_);
    }
    /// The alternative, for code that hoists the dispatch out of an inner loop (std::visit on it).
    const Variant& variant() const { return p_; }

  private:
    Variant p_;
};

}  // namespace shvol
