// The constants of one interaction, built once when its physics is created (and again when a saved
// scene is loaded): the contact's, and those of the model selected in every slot of SubModels.hpp.
// The per-step kernel (PairKernel.hpp) reads them and nothing else that is fixed.
#pragma once
#include "HertzMindlin.hpp"
#include "SubModels.hpp"
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
	return k;
}

} // namespace viscbridge
