// Law2_ScGeom_ViscBridgePhys_HertzViscous: Hertz–Mindlin contact with Coulomb friction plus the
// liquid-bridge forces selected for the interaction (physics.md §2, §8), with energy tracking.  Each
// interaction runs the kernel compiled for its models (core/models/Registry.hpp).
#pragma once
#include "viscbridge/yade/ViscBridgePhys.hpp"
#include "viscbridge/core/models/EnergyKeys.hpp"
#include "viscbridge/yade/AttributeRollback.hpp"
#include "viscbridge/yade/FilmSource.hpp"
#include <array>
#include <core/Dispatching.hpp>
#include <pkg/dem/ScGeom.hpp>
#include <atomic>

namespace yade {

class ViscBridgeContext;

class Law2_ScGeom_ViscBridgePhys_HertzViscous : public LawFunctor {
	AttributeRollback<std::string> rollback;
	// What the law looks up once per step (the first interaction of the step does it, the others wait).
	std::atomic<long>             stepIter { -1 };
	const Scene*                  stepScene = nullptr;
	bool                          stepImplicit = false; // the scheme in use is implicit (SchemeChooser.hpp) and the solver is there
	const FilmSource*             stepFilms = nullptr; // O.engines' ViscBridgeLiquid, if any
	bool                          stepSummed = false;  // forcesSummedAfterLoop()
	void                          beginStep();
	void                          reportMissingSolver();
	void                          reportMissingLiquidEngine();

public:
	// The scene's context for this step: where the kernels publish bridge events and book the work
	// of conservative forces (held, so that it outlives a scene replaced under the law).
	shared_ptr<ViscBridgeContext> context;
	// O.energy slots of the keys (core/models/EnergyKeys.hpp), resolved on first use.
	std::array<int, viscbridge::energyKeyCount> energyIndex;
	int integrationIndex = 0; // parsed `integration`
	void addEnergy(Real value, viscbridge::EnergyKey key);
	// Whether bodies id1 and id2 carry liquid for a bridge of liquidModel 'film' (physics.md L0, L5); read
	// only where the bridge would form (a rare path), so 'fixed' scenes never look at the films.
	bool filmsCanForm(Body::id_t id1, Body::id_t id2);
	// Whether a bridge forms from the films: its physics says so, or the scene keeps films (a
	// ViscBridgeLiquid in O.engines).  The second covers the first step after O.load, when the
	// physics' unsaved liquidModel still reads 'fixed' until the engine restores it after the loop.
	bool formsFromFilms(const ViscBridgePhys& ph) const { return ph.constants.fromFilms || stepFilms; }
	// This step, a ViscBridgeForceSum after the loop adds the forces to the bodies (kept in the context until then).
	bool forcesSummedAfterLoop() const { return stepSummed; }

	bool go(shared_ptr<IGeom>& geom, shared_ptr<IPhys>& phys, Interaction* interaction) override;
	void postLoad(Law2_ScGeom_ViscBridgePhys_HertzViscous&);
	FUNCTOR2D(ScGeom, ViscBridgePhys);
	// clang-format off
	Real capillaryInput() const; // −capillaryWork with the last step's work, not booked yet
	std::string integrationInUseName() const; // the scheme now: `integration`, or the one ViscBridgeTimeStepper chose
	YADE_CLASS_BASE_DOC_ATTRS_CTOR_PY(Law2_ScGeom_ViscBridgePhys_HertzViscous, LawFunctor,
		"Hertz–Mindlin contact with Coulomb friction (as :yref:`Law2_ScGeom_MindlinPhys_Mindlin`, "
		"optionally with contact damping) plus the viscous forces of a liquid bridge: normal "
		"$F=-C^n v_r^n$ (P3) and the tangential model chosen in "
		":yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys`, with the gap clamped at $S_{min}$ also in "
		"overlap, so the force is continuous through contact (P6). The interaction lives while there "
		"is a contact or a bridge; a bridge forms at contact (or within formationDistance) and "
		"ruptures beyond $S_{rup}$ (P11); every formation and rupture is published as a bridge event for the "
		"engines of the scene (:yref:`ViscBridgeContext`).\n\n"
		"Only the selected effects are evaluated: each interaction runs a kernel compiled for its "
		"combination of models, so an unselected effect costs nothing. The capillary force "
		"(:yref:`Ip2_FrictMat_FrictMat_ViscBridgePhys.capillaryModel`) is always explicit: it depends on the "
		"gap only and is part of the other forces of the implicit solve.\n\n"
		"With :yref:`O.trackEnergy<Omega.trackEnergy>`, adds to ``O.energy``: ``viscDissipNormal``, "
		"``viscDissipTangential`` (sliding part of the tangential dissipation), "
		"``viscDissipRotational`` (the part that resists rolling; negative only with 'washino', which "
		"is not dissipative), ``contactDampDissip`` (with en<1), ``plastDissip`` (friction), ``capillaryWork`` (minus the work "
		"of the capillary forces, P21) — all cumulative — and ``elastPotential`` (current Hertz–Mindlin elastic energy). The viscous "
		"dissipation of a step is the work of that step's forces, evaluated from the velocities the "
		"forces were computed with and the velocities that followed ($W=F\\cdot(v_{n-1/2}+v_{n+1/2})/2\\,\\Delta t$, "
		"booked at the next step, when $v_{n+1/2}$ is known): it matches the kinetic energy YADE's "
		"leapfrog reports, so ``O.energy.total()`` stays near 0 at any stable time step.",
		((string,integration,"explicit",Attr::triggerPostLoad,"Time integration of the viscous forces: 'explicit' (the paper's framework: forces from the velocities the integrator stores; stable for $\\Delta t<2t_v$, P12) or 'implicit' (backward Euler over the contact network, P15, solved by :yref:`ViscBridgeImplicitSolver`, which must be in O.engines; unconditionally stable for the viscous part). With :yref:`ViscBridgeTimeStepper.autoIntegration` the stepper chooses the scheme per phase of the run, and this is the scheme the run starts with (integrationInUse says which runs)."))
		,
		/* ctor */ energyIndex.fill(-1); rollback.keep(std::tie(integration));
		,
		/* py */
		.add_property("integrationInUse", &Law2_ScGeom_ViscBridgePhys_HertzViscous::integrationInUseName,
		              "The scheme of the viscous forces now, 'explicit' or 'implicit': :yref:`integration<Law2_ScGeom_ViscBridgePhys_HertzViscous.integration>`, "
		              "or, once a :yref:`ViscBridgeTimeStepper` with autoIntegration has chosen, its choice (it never changes integration).")
		.add_property("capillaryInput", &Law2_ScGeom_ViscBridgePhys_HertzViscous::capillaryInput,
		              "Energy the capillary forces have put into the particles since this law was created [J], with or "
		              "without energy tracking (P21): minus the work booked as ``O.energy['capillaryWork']``, which books a "
		              "step's work once the following velocities are known, plus the last step's, estimated with the "
		              "velocity it was recorded with. Stability checks add it to the released potential energy.")
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(Law2_ScGeom_ViscBridgePhys_HertzViscous);

} // namespace yade
