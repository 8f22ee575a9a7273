// ViscBridgeTimeStepper: sets O.dt from the live contacts and bridges (physics.md §3, P14).
#pragma once
#include <core/TimeStepper.hpp>

namespace yade {

// P14 over the live interactions (without the safety factor); see ViscBridgeTimeStepper.
struct NetworkTimeStepBound {
	Real       collision = 0, viscous = 0, combined = 0; // [s], inf when nothing bounds them
	Body::id_t criticalBody = -1;
	// per-thread, per-body rates of P14, kept to be reused between calls
	std::vector<Real> rates;
	// the smallest rayleighFraction × T_R over the spheres, cached while the bodies stay the same
	Real       rayleigh = 0, rayleighFractionUsed = -1;
	Body::id_t rayleighBody = -1;
	long       rayleighSignature = -1;
	void              evaluate(Scene* scene, bool viscousImplicit, Real rayleighFraction);
};

class ViscBridgeTimeStepper : public TimeStepper {
	NetworkTimeStepBound bound;
	size_t               validatedSignature = 0; // sceneSignature() of the last validated scene
	Real              lastValidSafety = 0.5, lastValidGrowth = 1.1, lastValidRayleigh = 0.4, lastValidMaxDt = 0;

public:
	void computeTimeStep(Scene*) override;
	bool isActivated() override;
	void postLoad(ViscBridgeTimeStepper&);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(ViscBridgeTimeStepper, TimeStepper,
		"Sets :yref:`O.dt<Omega.dt>` = safety × the rigorous network bound P14 of physics §3, "
		"evaluated over the live interactions every timeStepUpdateInterval steps:\n\n"
		"$\\Delta t \\le \\min_i 4/(d_i+\\sqrt{d_i^2+4\\kappa_i})$, with "
		"$d_i=\\sum_j (C_n + w_t C_t)(1/m_i+1/m_j)$ and $\\kappa_i=\\sum_j (k_n+3.5k_s)(1/m_i+1/m_j)$ "
		"($1/m_j=0$ for walls, facets, boxes and fixed bodies). The viscous coefficients are taken at "
		"$S_{min}$, where they are largest, for every existing bridge "
		"(:yref:`ViscBridgePhys.viscousStepCoefficient`); elastic and contact-damping terms use the "
		"current Hertz–Mindlin stiffness. Springs and dashpots are combined (P13/P14), not "
		"min()-ed: the min of the separate limits is up to 1.6× too optimistic. Unlike "
		":yref:`GlobalStiffnessTimeStepper` (whose viscous branch sits 1.3–1.8× above the true limit), "
		"the bound is sufficient; on real packings it is 1.5–3× below the true limit.\n\n"
		"Spheres also obey rayleighFraction × their Rayleigh time (the usual collision criterion), so "
		"that collisions are resolved before any contact exists. With "
		":yref:`Law2_ScGeom_ViscBridgePhys_HertzViscous.integration` = 'implicit', the viscous part is "
		"dropped (P15) and the collision part governs. The default safety 0.5 puts a dashpot-dominated "
		"pair at $t_v$: stable (limit $2t_v$) and free of spurious rebound.\n\n"
		"Under yade.mpy (docs/cluster.md) the bound is the minimum over the ranks, so that every rank sets the same dt; "
		"a dt that differs between ranks stops every rank.",
		((Real,safety,0.5,Attr::triggerPostLoad,"Fraction of the bound used as time step, in (0, 1]."))
		((Real,maxGrowth,1.1,Attr::triggerPostLoad,"Largest factor by which dt may grow in one update, >= 1 (decreases apply at once)."))
		((Real,rayleighFraction,0.4,Attr::triggerPostLoad,"Collision bound of a sphere: rayleighFraction × its Rayleigh time T_R, in (0, 1] (0.4 × safety 0.5 = the customary 0.2 T_R)."))
		((Real,maxDt,0,Attr::triggerPostLoad,"Upper limit of dt [s], >= 0; 0: none."))
		((Real,dtCollision,0,Attr::readonly,"safety × the collision bound alone: springs and contact damping (P14 with the bridges left out) and the Rayleigh bound [s]."))
		((Real,dtViscous,0,Attr::readonly,"safety × the viscous bound alone, $\\min_i 2/d_i$ over the bridges (inf without bridges or with implicit integration) [s]. For an equal pair held below $S_{min}$ it is safety × $2t_v$."))
		((Real,dtBound,0,Attr::readonly,"safety × the combined bound (before the growth limit) [s]."))
		((string,governing,"collision",Attr::readonly,"'viscous' if dtViscous < dtCollision, else 'collision'."))
		((int,criticalBody,-1,Attr::readonly,"Id of the body whose bound is the smallest (-1 if none)."))
		,
		/* ctor */ timeStepUpdateInterval = 1;
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(ViscBridgeTimeStepper);

} // namespace yade
