// ViscBridgePhys: Hertz–Mindlin contact state plus a liquid bridge (physics.md §2, §8).
#pragma once
#include "viscbridge/core/pair/PairKernel.hpp"
#include "viscbridge/core/pair/PairRecord.hpp"
#include <pkg/dem/FrictPhys.hpp>

namespace yade {

class ViscBridgePhys : public FrictPhys {
public:
	virtual ~ViscBridgePhys() = default;
	// This bridge's rates in the bound P14 (physics.md §3): its damping at S_min and its capillary
	// stiffness per unit reduced mass [1/s, 1/s²].
	Real stepDampingRate() const { return mEff > 0 ? viscousStepCoefficient / mEff : 0; }
	Real stepStiffnessRate() const { return mEff > 0 ? capillaryStiffness / mEff : 0; }
	// Built from the attributes below when the physics is created and after a scene is loaded
	// (never saved): the constants the law's kernel reads, and which kernel that is.
	viscbridge::PairConstants  constants;
	viscbridge::ModelSelection selection;
	std::size_t                kernel = 0;
	// With implicit integration: the bridge's damping as described by the law in step
	// implicitBlockIter, for ViscBridgeImplicitSolver (not saved: rebuilt every step).
	viscbridge::ViscousBlock implicitBlock;
	long                     implicitBlockIter = -1;
	// [accuracy] The block the implicit solver used at step solvedIter, whose Δt was solvedDt: the
	// change of the bridge's coefficients since then is an error of the step (physics.md A1c).
	viscbridge::ViscousBlock solvedBlock;
	long                     solvedIter = -1;
	double                   solvedDt = 0, solvedGap = 0;
	// The inputs the constants are built from (the attributes below, once they are set).
	viscbridge::BridgeInputs bridgeInputs() const;
	// Builds the constants for the models of `s` (whose names the attributes hold).
	void buildConstants(const viscbridge::ModelSelection& s);
	// After loading: the models from their saved names (std::invalid_argument for an unknown one).
	void postLoad(ViscBridgePhys&);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(ViscBridgePhys, FrictPhys,
		"Physics of a wet contact: Hertz–Mindlin contact (constants of "
		":yref:`Ip2_FrictMat_FrictMat_MindlinPhys`) and a liquid bridge with its viscous and capillary "
		"forces, created by :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys` and evaluated by "
		":yref:`Law2_ScGeom_ViscBridgePhys_HertzViscous`. The models are saved with the scene by name.\n\n"
		"Vector forces named ``…ContactForce``/``…ViscousForce``/``capillaryForce`` act on body 1 (body 2 "
		"receives the opposite force); the inherited :yref:`NormShearPhys.normalForce` and "
		":yref:`NormShearPhys.shearForce` keep YADE's meaning (total force sustained by body 2), so "
		"YADE's stress and force utilities see contact, viscous and capillary forces together.",
		// the per-contact record: its state and outputs (core/pair/PairRecord.hpp, the one list of them)
		VISCBRIDGE_PAIR_RECORD_ATTRS
		// the pair and the liquid, fixed when the physics is created
		((Real,kno,0,Attr::readonly,"Hertz coefficient: normal force $F_n=k_{no}\\delta^{3/2}$ [N/m^{3/2}]."))
		((Real,kso,0,Attr::readonly,"Mindlin coefficient: tangential stiffness $k_s=k_{so}\\delta^{1/2}$ [N/m^{3/2}]."))
		((Real,betan,0,Attr::readonly,"Normal contact damping ratio (from :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys.en`)."))
		((Real,betas,0,Attr::readonly,"Tangential contact damping ratio (equal to betan)."))
		((Real,radius1,0,Attr::readonly,"True radius of body 1; 0 if body 1 is not a sphere (wall, facet, box) [m]."))
		((Real,radius2,0,Attr::readonly,"True radius of body 2; 0 if body 2 is not a sphere [m]."))
		((Real,rEff,0,Attr::readonly,"Reduced radius $\\bar r$ (physics.md §1): $r_1r_2/(r_1+r_2)$, or the sphere's radius against a wall [m]."))
		((Real,mEff,0,Attr::readonly,"Reduced mass $m^*$: $m_1m_2/(m_1+m_2)$, or the dynamic body's mass against a wall or fixed body [kg]."))
		((string,normalModel,"none",Attr::readonly,"Normal viscous model of this interaction ('none' when dry); see :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys.normalModel`."))
		((string,tangentialModel,"none",Attr::readonly,"Tangential viscous model of this interaction ('none' when dry)."))
		((string,capillaryModel,"none",Attr::readonly,"Capillary model of this interaction ('none' without surface tension)."))
		((Real,viscosity,0,Attr::readonly,"Liquid viscosity $\\mu$ [Pa·s]."))
		((Real,surfaceTension,0,Attr::readonly,"Surface tension $\\gamma$ [N/m]."))
		((Real,contactAngle,0,Attr::readonly,"Contact angle $\\theta$ [rad]."))
		((Real,bridgeVolume,0,Attr::readonly,"Bridge volume $V$ [m³]: fixed when the physics is created (liquidModel 'fixed'), or taken from the particles' films when the bridge forms (liquidModel 'film'; until then, the largest volume it may take)."))
		((string,liquidModel,"fixed",Attr::readonly|Attr::noSave,"Where the bridge's liquid comes from: 'fixed' (a volume of its own) or 'film' (the particles' films, given back at rupture); see :yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys.liquidModel`. Not saved (scenes saved before it existed keep loading): after loading, :yref:`ViscBridgeLiquid` restores it."))
		((Real,sMin,0,Attr::readonly,"Minimum gap $S_{min}$ at which the viscous coefficients are evaluated (P6) [m]."))
		((Real,sRup,0,Attr::readonly,"Rupture distance $S_{rup}=(1+\\theta/2)V^{1/3}$ (P11) [m]."))
		((Real,formationDistance,0,Attr::readonly,"The bridge forms when $S$ falls below this distance (0: at contact) [m]."))
		((Real,viscousStepCoefficient,0,Attr::readonly|Attr::noSave,"$C_n + w_tC_t$ at $S_{min}$: the largest viscous damping of this bridge as the time step sees it (P14, P14a) [N·s/m]."))
		((Real,capillaryStiffness,0,Attr::readonly|Attr::noSave,"The largest $|dF/dS|$ of the capillary force over the bridge's life (P22) [N/m]."))
		, /* ctor */ createIndex();
	);
	// clang-format on
	REGISTER_CLASS_INDEX(ViscBridgePhys, FrictPhys);
};
REGISTER_SERIALIZABLE(ViscBridgePhys);

} // namespace yade
