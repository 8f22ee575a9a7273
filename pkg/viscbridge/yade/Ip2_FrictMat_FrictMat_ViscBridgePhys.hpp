// Ip2_FrictMat_FrictMat_ViscBridgePhys: creates ViscBridgePhys for two FrictMat bodies, with the
// sub-models the scene selected (physics.md §2, §8; the models are listed in core/models/Registry.hpp,
// the numeric parameters' ranges in core/models/Parameters.hpp).
#pragma once
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include "viscbridge/core/models/Parameters.hpp"
#include "viscbridge/core/liquid/FilmExchange.hpp"
#include "viscbridge/yade/AttributeRollback.hpp"
#include <atomic>
#include <core/Dispatching.hpp>
#include <pkg/common/ElastMat.hpp>

namespace yade {

class Ip2_FrictMat_FrictMat_ViscBridgePhys : public IPhysFunctor {
	// Every checked attribute: a rejected assignment is undone.
	AttributeRollback<Real, Real, Real, Real, Real, Real, Real, Real, Real, std::string, std::string, std::string, std::string> rollback;
	auto checked()
	{
		return std::tie(viscosity, bridgeVolume, bridgeVolumeRel, contactAngle, sMin, sMinRel, formationDistance, en, surfaceTension, normalModel,
		                tangentialModel, capillaryModel, liquidModel);
	}
	Real& numeric(std::size_t i); // the attribute of parameters::all[i]
	const Scene* usedIn = nullptr; // the scene whose interactions this functor has built
	void         warnExistingKeepTheirs() const;
	void         warnIneffectiveOrImplausible() const; // legal values that are almost surely a mistake
	std::atomic<bool> warnedBridgeSize { false };       // a bridge larger than its particles (once)
	void              warnBridgeSize(Real volume, Real particleVolume, Real sRup, Real radius);

public:
	viscbridge::ModelSelection selection; // parsed normalModel, tangentialModel, capillaryModel
	void validate();                      // throws std::invalid_argument
	void postLoad(Ip2_FrictMat_FrictMat_ViscBridgePhys&);
	// The liquid model a loaded scene had (liquidModel is not saved; ViscBridgeLiquid restores it):
	// not a change by the user, so without postLoad's warnings about existing interactions.
	void restoreLiquidModel(const std::string& model);
	void go(const shared_ptr<Material>& b1, const shared_ptr<Material>& b2, const shared_ptr<Interaction>& interaction) override;
	FUNCTOR2D(FrictMat, FrictMat);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(Ip2_FrictMat_FrictMat_ViscBridgePhys, IPhysFunctor,
		"Creates :yref:`ViscBridgePhys`: Hertz–Mindlin contact constants as "
		":yref:`Ip2_FrictMat_FrictMat_MindlinPhys` (minimum friction angle of the two materials), "
		"and a liquid bridge with the selected viscous (normal, tangential) and capillary models.\n\n"
		"A bridge exists when the liquid does something: a viscosity > 0, or a capillary model with a "
		"surface tension > 0 (surface tension alone gives a capillary bridge without viscous forces). "
		"Per pair, $\\bar r$ and $m^*$ come from the bodies themselves: a wall, facet or box side has "
		"$\\bar r = r_{sphere}$ and $m^* = m_{sphere}$ (the artificial radius YADE's geometry functors "
		"report for such sides only enters the Hertz constants, exactly as in YADE's own Mindlin law). "
		"Invalid values raise ValueError on assignment and leave the previous value in place.",
		((Real,viscosity,viscbridge::parameters::viscosity.defaultValue,Attr::triggerPostLoad,"Liquid viscosity $\\mu$ [Pa·s], >= 0. 0 means no viscous force, at no cost."))
		((Real,bridgeVolume,viscbridge::parameters::bridgeVolume.defaultValue,Attr::triggerPostLoad,"Bridge volume $V$ [m³], >= 0 (with liquidModel 'film': the largest volume a bridge takes from the films). 0 means: use :yref:`bridgeVolumeRel<Ip2_FrictMat_FrictMat_ViscBridgePhys.bridgeVolumeRel>`."))
		((Real,bridgeVolumeRel,viscbridge::parameters::bridgeVolumeRel.defaultValue,Attr::triggerPostLoad,"Bridge volume as a fraction of the mean volume of the two particles (of the sphere, against a wall), in (0, 1]; used when bridgeVolume is 0 (with liquidModel 'film': the largest fraction a bridge takes from the films)."))
		((Real,contactAngle,viscbridge::parameters::contactAngle.defaultValue,Attr::triggerPostLoad,"Contact angle $\\theta$ [rad], in [0, π/2]; enters the rupture distance $S_{rup}=(1+\\theta/2)V^{1/3}$ (Lian et al., P11) and the capillary force (P19, P20)."))
		((Real,sMin,viscbridge::parameters::sMin.defaultValue,Attr::triggerPostLoad,"Minimum gap $S_{min}$ [m], >= 0: the viscous coefficients are evaluated at $\\max(S,S_{min})$, also in overlap (P6). 0 means: $S_{min}$ = sMinRel·$\\bar r$."))
		((Real,sMinRel,viscbridge::parameters::sMinRel.defaultValue,Attr::triggerPostLoad,"$S_{min}/\\bar r$ when sMin is 0, in (0, 1]. It caps the force: at the same approach speed the force at contact is $\\propto 1/S_{min}$ and the stable explicit time step $\\propto S_{min}$. Note that LIGGGHTS clamps at minSeparationDistanceRatio × $\\bar r$ and documents a value near 1, i.e. $S_{min}\\approx\\bar r$, a force cap about 100× too low; here 1e-3 is a typical roughness-scale value."))
		((string,normalModel,viscbridge::NormalSlot::defaultModel,Attr::triggerPostLoad,"Normal viscous force $F=-C^n v_r^n$: 'none', 'adamsPerchard' ($C^n=6\\pi\\mu\\bar r^2/S$, P4) or 'pitois' (P5, the finite-volume correction; tends to adamsPerchard as $V\\to\\infty$)."))
		((string,tangentialModel,viscbridge::TangentialSlot::defaultModel,Attr::triggerPostLoad,"Tangential viscous force: 'none'; 'slip' (default; $F=-C_T(v_r^t+\\tilde\\omega_r\\times n)$ with mid-gap arms, always dissipative, P7a); 'goldman' (symmetric resistance form with $C_T, C_R, C_W$, dissipative, faithful near a wall, P7b); 'washino' (the paper's P7, $F=-(C_Tv_r^t+C_R\\,\\omega_r\\times n)$, reproduced exactly; *not dissipative*: a sliding sphere can gain kinetic energy, and it cannot be integrated implicitly). Coefficients: Goldman's small-gap forms P8, P9 with +0.2526."))
		((string,capillaryModel,viscbridge::CapillarySlot::defaultModel,Attr::triggerPostLoad,"Capillary force of the bridge, an attraction along the normal that acts from the bridge's formation to its rupture and is held at its contact value in overlap (physics.md §8): 'none' (default), 'willett' (Willett et al. 2000, closed form, P19: $F=2\\pi R\\gamma\\cos\\theta/(1+2.1s^++10s^{+2})$, $s^+=(S/2)\\sqrt{R/V}$) or 'rabinovich' (Rabinovich et al. 2005, fixed volume, P20); both with the Derjaguin radius $R=2\\bar r$ ($R=r$ for equal spheres, $2r$ against a wall). Needs surfaceTension > 0."))
		((Real,surfaceTension,viscbridge::parameters::surfaceTension.defaultValue,Attr::triggerPostLoad,"Surface tension $\\gamma$ of the liquid [N/m], >= 0 (water: 0.072); 0 means no capillary force. Used by capillaryModel."))
		((Real,formationDistance,viscbridge::parameters::formationDistance.defaultValue,Attr::triggerPostLoad,"A bridge forms when the gap falls below this distance [m], >= 0 (0: at contact). Needs interactions created before contact, within this distance: :yref:`viscbridge.engines()` sets the detection range of every geometry functor it adds (spheres and boxes through interactionDetectionFactor, walls and facets through :yref:`Ig2_Wall_Sphere_ViscBridgeScGeom` and :yref:`Ig2_Facet_Sphere_ViscBridgeScGeom`, which replace YADE's, whose interactions start at contact); with your own engine list, set them yourself."))
		((string,liquidModel,viscbridge::liquidModelNames[0],Attr::triggerPostLoad|Attr::noSave,"Where a bridge's liquid comes from (physics.md §11): 'fixed' (default; every bridge has the volume bridgeVolume or bridgeVolumeRel, from nowhere) or 'film' (a bridge forms only where the particles carry liquid — :yref:`ViscBridgeState.film` — takes its volume from their films when it forms, at most bridgeVolume/bridgeVolumeRel, and gives it back when it ruptures; needs a :yref:`ViscBridgeLiquid` engine after the InteractionLoop, which :yref:`viscbridge.engines()` inserts). Walls and facets carry no film: a bridge to them takes its liquid from the particle alone. A body with :yref:`ViscBridgeState.wettable` False forms no bridge (either model). Changing it applies to interactions created afterwards. Not saved (scenes saved before it existed keep loading): a loaded scene with a ViscBridgeLiquid engine gets 'film' back at its first step."))
		((Real,en,viscbridge::parameters::en.defaultValue,Attr::triggerPostLoad,"Coefficient of restitution of the dry Hertz–Mindlin contact, in (0, 1]; 1 = no contact damping (no cost). Damping ratio from Thornton et al. (2013), as YADE's Ip2_FrictMat_FrictMat_MindlinPhys.en (P2b)."))
		,
		/* ctor */ rollback.keep(checked()); validate();
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(Ip2_FrictMat_FrictMat_ViscBridgePhys);

} // namespace yade
