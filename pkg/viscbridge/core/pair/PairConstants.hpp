// The constants of one interaction, built once when its physics is created (and again when a saved
// scene is loaded): the contact's, and those of the model selected in every slot of SubModels.hpp.
// The per-step kernel (PairKernel.hpp) reads them and nothing else that is fixed.
#pragma once
#include "viscbridge/core/models/contact/HertzMindlin.hpp"
#include "viscbridge/core/models/Registry.hpp"
#include <utility>

namespace viscbridge {

// The model chosen in each slot, as indices into its list (run-time only; scenes save names).
struct ModelSelection {
	std::size_t normal = 0, tangential = 0, damping = 0, capillary = 0;
};

// Which of the compiled kernels (Law2_…HertzViscous) an interaction runs.
inline std::size_t comboIndex(const ModelSelection& s)
{
	return ((s.normal * TangentialModels::size + s.tangential) * DampingModels::size + s.damping) * CapillaryModels::size + s.capillary;
}
inline constexpr std::size_t comboCount = NormalModels::size * TangentialModels::size * DampingModels::size * CapillaryModels::size;

// Whether the selection has anything that makes a liquid bridge (and keeps the interaction beyond contact).
inline bool hasBridge(const ModelSelection& s)
{
	return NormalModels::capabilities[s.normal].beyondContact || TangentialModels::capabilities[s.tangential].beyondContact
	        || CapillaryModels::capabilities[s.capillary].beyondContact;
}

struct PairConstants {
	HertzMindlinConstants                           contact {};
	double                                          mEff = 0, sMin = 0, sRup = 0, formationDistance = 0;
	ConstantsStorage<NormalModels::largest>         normal;
	ConstantsStorage<TangentialModels::largest>     tangential;
	ConstantsStorage<DampingModels::largest>        damping;
	ConstantsStorage<CapillaryModels::largest>      capillary;
	double viscousStepCoefficient = 0; // Σ of the slots' damping at its stiffest, for the time step (P14, P14a) [N·s/m]
	double capillaryStiffness     = 0; // the largest |dF/dS| of the capillary force (P22) [N/m]
	// the bridge's viscous coefficients at S_min, where they are largest (the time step's damping, P16)
	double               stiffestNormal = 0;
	TangentialResistance stiffestTangential;
	double               armGapFraction = 0; // of the tangential model: its arms reach r + fraction·S
	bool                 fromFilms      = false; // the bridge takes its volume from the films (physics.md L0)
};

namespace detail {
	// models with a stiffness of their own (the capillary ones) say so with stepStiffness()
	template <class M, class = void> struct HasStepStiffness : std::false_type {};
	template <class M> struct HasStepStiffness<M, std::void_t<decltype(std::declval<M>().stepStiffness(BridgeInputs()))>> : std::true_type {};

	template <class List, std::size_t Bytes>
	void storeModel(std::size_t index, const BridgeInputs& in, ConstantsStorage<Bytes>& storage, double& stepCoefficient, double& stepStiffness)
	{
		visitModel(index, List(), [&](auto i) {
			using M       = typename List::template At<decltype(i)::value>;
			const M model = M::make(in);
			storage.store(model);
			stepCoefficient += model.stepCoefficient(in);
			if constexpr (HasStepStiffness<M>::value) stepStiffness += model.stepStiffness(in);
		});
	}
}

inline PairConstants makePairConstants(const ModelSelection& s, const HertzMindlinConstants& contact, const BridgeInputs& in, double formationDistance)
{
	PairConstants k;
	k.contact           = contact;
	k.mEff              = in.mEff;
	k.sMin              = in.sMin;
	k.sRup              = in.sRup;
	k.formationDistance = formationDistance;
	detail::storeModel<NormalModels>(s.normal, in, k.normal, k.viscousStepCoefficient, k.capillaryStiffness);
	detail::storeModel<TangentialModels>(s.tangential, in, k.tangential, k.viscousStepCoefficient, k.capillaryStiffness);
	detail::storeModel<DampingModels>(s.damping, in, k.damping, k.viscousStepCoefficient, k.capillaryStiffness);
	detail::storeModel<CapillaryModels>(s.capillary, in, k.capillary, k.viscousStepCoefficient, k.capillaryStiffness);
	visitModel(s.normal, NormalModels(), [&](auto i) { k.stiffestNormal = k.normal.as<NormalModels::At<decltype(i)::value>>().coefficient(in.sMin); });
	visitModel(s.tangential, TangentialModels(), [&](auto i) {
		using T = TangentialModels::At<decltype(i)::value>;
		k.armGapFraction = T::armGapFraction;
		if constexpr (T::capabilities.enabled) {
			const TangentialKinematics still { Vec3::UnitX(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), in.radius1, in.radius2, in.sMin, in.sMin };
			k.stiffestTangential = k.tangential.as<T>().evaluate(still).resistance;
		}
	});
	return k;
}

} // namespace viscbridge
