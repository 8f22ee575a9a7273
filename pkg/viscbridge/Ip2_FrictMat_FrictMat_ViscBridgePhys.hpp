// Ip2_FrictMat_FrictMat_ViscBridgePhys: creates ViscBridgePhys for two FrictMat bodies, composing
// the viscous sub-models the scene selected (physics.md §2).
#pragma once
#include "ViscBridgePhys.hpp"
#include <core/Dispatching.hpp>
#include <pkg/common/ElastMat.hpp>

namespace yade {

class Ip2_FrictMat_FrictMat_ViscBridgePhys : public IPhysFunctor {
	// The last parameter set that passed validation: a rejected assignment is undone.
	struct Parameters {
		Real        viscosity, bridgeVolume, bridgeVolumeRel, contactAngle, sMin, sMinRel, formationDistance, en;
		std::string normalModel, tangentialModel;
	};
	Parameters lastValid;
	Parameters current() const;
	void       restore(const Parameters&);

public:
	int  normalModelIndex     = 1; // parsed normalModel
	int  tangentialModelIndex = 2; // parsed tangentialModel
	void validate();               // throws std::invalid_argument
	void postLoad(Ip2_FrictMat_FrictMat_ViscBridgePhys&);
	void go(const shared_ptr<Material>& b1, const shared_ptr<Material>& b2, const shared_ptr<Interaction>& interaction) override;
	FUNCTOR2D(FrictMat, FrictMat);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(Ip2_FrictMat_FrictMat_ViscBridgePhys, IPhysFunctor,
		"Creates :yref:`ViscBridgePhys`: Hertz–Mindlin contact constants as "
		":yref:`Ip2_FrictMat_FrictMat_MindlinPhys` (minimum friction angle of the two materials), "
		"and a viscous liquid bridge with the selected normal and tangential models.\n\n"
		"Per pair, $\\bar r$ and $m^*$ come from the bodies themselves: a wall, facet or box side has "
		"$\\bar r = r_{sphere}$ and $m^* = m_{sphere}$ (the artificial radius YADE's geometry functors "
		"report for such sides only enters the Hertz constants, exactly as in YADE's own Mindlin law). "
		"Invalid values raise ValueError on assignment and leave the previous value in place.",
		((Real,viscosity,0,Attr::triggerPostLoad,"Liquid viscosity $\\mu$ [Pa·s], >= 0. 0 means dry: no bridge and no viscous force, at no cost."))
		((Real,bridgeVolume,0,Attr::triggerPostLoad,"Bridge volume $V$ [m³], >= 0. 0 means: use :yref:`bridgeVolumeRel<Ip2_FrictMat_FrictMat_ViscBridgePhys.bridgeVolumeRel>`."))
		((Real,bridgeVolumeRel,0.01,Attr::triggerPostLoad,"Bridge volume as a fraction of the mean volume of the two particles (of the sphere, against a wall), > 0; used when bridgeVolume is 0."))
		((Real,contactAngle,0,Attr::triggerPostLoad,"Contact angle $\\theta$ [rad], in [0, π/2]; enters the rupture distance $S_{rup}=(1+\\theta/2)V^{1/3}$ (Lian et al., P11)."))
		((Real,sMin,0,Attr::triggerPostLoad,"Minimum gap $S_{min}$ [m], >= 0: the viscous coefficients are evaluated at $\\max(S,S_{min})$, also in overlap (P6). 0 means: $S_{min}$ = sMinRel·$\\bar r$."))
		((Real,sMinRel,1e-3,Attr::triggerPostLoad,"$S_{min}/\\bar r$ when sMin is 0, in (0, 1]. It caps the force: at the same approach speed the force at contact is $\\propto 1/S_{min}$ and the stable explicit time step $\\propto S_{min}$. Note that LIGGGHTS clamps at minSeparationDistanceRatio × $\\bar r$ and documents a value near 1, i.e. $S_{min}\\approx\\bar r$, a force cap about 100× too low; here 1e-3 is a typical roughness-scale value."))
		((string,normalModel,"adamsPerchard",Attr::triggerPostLoad,"Normal viscous force $F=-C^n v_r^n$: 'none', 'adamsPerchard' ($C^n=6\\pi\\mu\\bar r^2/S$, P4) or 'pitois' (P5, the finite-volume correction; tends to adamsPerchard as $V\\to\\infty$)."))
		((string,tangentialModel,"slip",Attr::triggerPostLoad,"Tangential viscous force: 'none'; 'slip' (default; $F=-C_T(v_r^t+\\tilde\\omega_r\\times n)$ with mid-gap arms, always dissipative); 'goldman' (symmetric resistance form with $C_T, C_R, C_W$, dissipative, faithful near a wall); 'washino' (the paper's P7, $F=-(C_Tv_r^t+C_R\\,\\omega_r\\times n)$, reproduced exactly; *not dissipative*: a sliding sphere can gain kinetic energy). Coefficients: Goldman's small-gap forms P8, P9 with +0.2526."))
		((Real,formationDistance,0,Attr::triggerPostLoad,"A bridge forms when the gap falls below this distance [m], >= 0 (0: at contact). Needs interactions created before contact, within this distance: :yref:`viscbridge.engines()` sets the detection range of every geometry functor it adds (spheres and boxes through interactionDetectionFactor, walls and facets through :yref:`Ig2_Wall_Sphere_ViscBridgeScGeom` and :yref:`Ig2_Facet_Sphere_ViscBridgeScGeom`, which replace YADE's, whose interactions start at contact); with your own engine list, set them yourself."))
		((Real,en,1,Attr::triggerPostLoad,"Coefficient of restitution of the dry Hertz–Mindlin contact, in (0, 1]; 1 = no contact damping (no cost). Damping ratio from Thornton et al. (2013), as YADE's Ip2_FrictMat_FrictMat_MindlinPhys.en."))
		,
		/* ctor */ lastValid = current();
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(Ip2_FrictMat_FrictMat_ViscBridgePhys);

} // namespace yade
