#include "viscbridge/yade/Law2_ScGeom_ViscBridgePhys_HertzViscous.hpp"
#include "viscbridge/yade/SchemeChooser.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/core/pair/PairKernel.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/yade/ViscBridgeState.hpp"
#include <core/Omega.hpp>
#include <core/Scene.hpp>
#include <array>
#include <tuple>
#include <utility>

namespace yade {

CREATE_LOGGER(Law2_ScGeom_ViscBridgePhys_HertzViscous);

namespace {
	using Law2 = Law2_ScGeom_ViscBridgePhys_HertzViscous;
	namespace vb = viscbridge;

	using Kernel = bool (*)(Law2&, ScGeom&, ViscBridgePhys&, Interaction*);

	// Books one model's energy of the step under the keys it declares (its energyKeys, physics.md §6):
	// into O.energy when tracking, and the work of a conservative model (capillary) always, for the guard.
	template <class M, bool E> void bookModel(Law2& law, const vb::PairEnergy& e)
	{
		for (const vb::EnergyKey key : M::energyKeys) {
			if constexpr (vb::booksWork<M>) law.context->conservativeWork += e[key];
			if constexpr (E) law.addEnergy(e[key], key);
		}
	}
	template <class Cm, bool E> void bookEnergy(Law2& law, const vb::PairEnergy& e)
	{
		bookModel<typename Cm::Normal, E>(law, e);
		bookModel<typename Cm::Tangential, E>(law, e);
		bookModel<typename Cm::Damping, E>(law, e);
		bookModel<typename Cm::Capillary, E>(law, e);
		if constexpr (E)
			for (const vb::EnergyKey key : vb::contactEnergyKeys)
				law.addEnergy(e[key], key);
	}

	// One interaction step with the models of Cm fixed at compile time; E: track energy; Imp: leave
	// the viscous forces to ViscBridgeImplicitSolver (the law describes them in the physics).
	template <class Cm, bool E, bool Imp> bool lawKernel(Law2& law, ScGeom& geom, ViscBridgePhys& ph, Interaction* I)
	{
		Scene*           scene = law.scene;
		const Body::id_t id1 = I->getId1(), id2 = I->getId2();
		const State*     s1 = Body::byId(id1, scene)->state.get();
		const State*     s2 = Body::byId(id2, scene)->state.get();
		const bool       periodic = scene->isPeriodic;
		const Vector3r   shift2   = periodic ? scene->cell->intrShiftPos(I->cellDist) : Vector3r::Zero();
		const Vector3r   shiftVel = periodic ? scene->cell->intrShiftVel(I->cellDist) : Vector3r::Zero();

		vb::PairInput in;
		in.n            = geom.normal;
		in.S            = -geom.penetrationDepth;
		in.contactPoint = geom.contactPoint;
		in.b1           = { s1->pos, s1->vel, s1->angVel, ph.radius1 };
		in.b2           = { s2->pos + shift2, s2->vel + shiftVel, s2->angVel, ph.radius2 };
		if constexpr (Cm::Damping::capabilities.enabled)
			in.contactRelVel = geom.getIncidentVel(s1, s2, scene->dt, shift2, shiftVel, /*avoidGranularRatcheting*/ false);
		in.shearIncrement = geom.shearIncrement();
		in.dt             = scene->dt;
		if (in.S <= 0) ph.shearElastic = geom.rotate(ph.shearElastic); // into the current contact frame
		if constexpr (Cm::hasBridge)
			if (!ph.bridge && law.formsFromFilms(ph) && vb::kernel::formsAt(ph.constants, in.S)) in.liquid = law.filmsCanForm(id1, id2);

		vb::PairForces f;
		vb::PairEnergy e;
		[[maybe_unused]] const bool hadBridge = ph.bridge;
		const bool                  lives     = vb::evaluatePair<Cm, E, Imp>(ph.constants, ph, in, f, e);
		if constexpr (Cm::hasBridge) // a formation or a rupture, for the engines that follow the bridges
			if (ph.bridge != hadBridge)
				law.context->publish({ ph.bridge ? BridgeEvent::Kind::formed : BridgeEvent::Kind::ruptured, id1, id2, ph.bridgeVolume, in.S,
				                       ph.stepDampingRate(), ph.stepStiffnessRate() });
		if (!lives) return false;
		if constexpr (Imp) ph.implicitBlockIter = scene->iter;
		if (law.forcesSummedAfterLoop()) // the same sums on any number of threads (YADE's per-thread force slots would depend on the schedule)
			law.context->keepForce({ I, id1, id2, f.force1, f.torque1, f.torque2 });
		else {
			scene->forces.addForce(id1, f.force1);
			scene->forces.addForce(id2, -f.force1);
			scene->forces.addTorque(id1, f.torque1);
			scene->forces.addTorque(id2, f.torque2);
		}
		// [MPI] an interaction shared by two ranks of yade.mpy is booked by one (always true serially)
		if constexpr (E || Cm::booksWorkAlways)
			if (distributed::ownershipThisStep(scene).interaction(*I, scene)) bookEnergy<Cm, E>(law, e);
		return true;
	}

	// The kernel of every combination of models, from the lists of SubModels.hpp: entry
	// (comboIndex(selection) * 2 + trackEnergy) * 2 + implicit.  A tangential model the implicit
	// solver cannot take gets its explicit kernel there (SceneValidation refuses the scene first).
	template <std::size_t K> constexpr Kernel kernelAt()
	{
		constexpr std::size_t imp = K % 2, energy = (K / 2) % 2, combo = K / 4;
		constexpr std::size_t c = combo % vb::CapillaryModels::size, d = (combo / vb::CapillaryModels::size) % vb::DampingModels::size;
		constexpr std::size_t t = (combo / (vb::CapillaryModels::size * vb::DampingModels::size)) % vb::TangentialModels::size;
		constexpr std::size_t n = combo / (vb::CapillaryModels::size * vb::DampingModels::size * vb::TangentialModels::size);
		using Cm = vb::Combo<vb::NormalModels::At<n>, vb::TangentialModels::At<t>, vb::DampingModels::At<d>, vb::CapillaryModels::At<c>>;
		constexpr bool implicitOk = imp == 1 && Cm::Tangential::capabilities.implicitCapable;
		return &lawKernel<Cm, energy == 1, implicitOk>;
	}
	template <std::size_t... K> constexpr std::array<Kernel, sizeof...(K)> makeKernelTable(std::index_sequence<K...>) { return { kernelAt<K>()... }; }
	constexpr auto kernels = makeKernelTable(std::make_index_sequence<vb::comboCount * 4>());
}

void Law2_ScGeom_ViscBridgePhys_HertzViscous::addEnergy(Real value, vb::EnergyKey key)
{
	int&                      index = energyIndex[static_cast<std::size_t>(key)];
	const vb::EnergyKeySpec& spec  = vb::spec(key);
	if (index < 0) {
		// The first lookup registers the name; registration must not race with other threads.
#ifdef YADE_OPENMP
#pragma omp critical(viscbridge_energy_index)
#endif
		scene->energy->add(value, spec.name, index, spec.reset);
		return;
	}
	scene->energy->add(value, spec.name, index, spec.reset);
}

void Law2_ScGeom_ViscBridgePhys_HertzViscous::postLoad(Law2_ScGeom_ViscBridgePhys_HertzViscous&)
{
	rollback.check(std::tie(integration), [&] {
		integrationIndex = static_cast<int>(vb::parseName("Law2_ScGeom_ViscBridgePhys_HertzViscous", "integration", integration, vb::integrationNames, "scheme"));
	});
}

void Law2_ScGeom_ViscBridgePhys_HertzViscous::beginStep()
{
	// Once per loop pass: the first interaction of the pass does it, the others wait.  A step YADE
	// repeats after an exception has the same iter: the context says its pass is new.
	if (stepIter.load(std::memory_order_acquire) == scene->iter && stepScene == scene && context->passOpen(scene->iter)) return;
#ifdef YADE_OPENMP
#pragma omp critical(viscbridge_law_step)
#endif
	{
		if (stepIter.load(std::memory_order_relaxed) != scene->iter || stepScene != scene || !context->passOpen(scene->iter)) {
			context    = ViscBridgeContext::shared(scene);
			stepSummed = ViscBridgeContext::hasEngineAfterLoop(scene, "ViscBridgeForceSum");
			context->beginStep(scene->iter, stepSummed);
			stepImplicit = integrationInUse(scene, integrationIndex) == vb::Integration::implicitEuler;
			if (stepImplicit && !ViscBridgeContext::hasEngine(scene, "ViscBridgeImplicitSolver")) {
				stepImplicit = false;
				reportMissingSolver();
			}
			stepFilms    = ViscBridgeContext::findEngine<FilmSource>(scene);
			stepScene        = scene;
			stepIter.store(scene->iter, std::memory_order_release);
		}
	}
}

void Law2_ScGeom_ViscBridgePhys_HertzViscous::reportMissingSolver()
{
	// Exceptions cannot leave InteractionLoop's parallel loop, so the error is raised by a
	// ViscBridgeGuard at the start of the next step (this step falls back to explicit forces).
	const std::string msg = "the implicit scheme (Law2_ScGeom_ViscBridgePhys_HertzViscous.integration='implicit', or chosen by "
	                        "ViscBridgeTimeStepper.autoIntegration) needs a ViscBridgeImplicitSolver engine between "
	                        "InteractionLoop and NewtonIntegrator, and O.engines has none (viscbridge.engines(integration='implicit') inserts it).";
	LOG_ERROR(msg << " This step used explicit viscous forces; the run stops.");
	context->raiseAtNextStep(scene, msg);
}

bool Law2_ScGeom_ViscBridgePhys_HertzViscous::filmsCanForm(Body::id_t id1, Body::id_t id2)
{
	if (!stepFilms) {
		reportMissingLiquidEngine();
		return false;
	}
	Real liquid = 0;
	for (const Body::id_t id : { id1, id2 })
		if (const ViscBridgeState* s = ViscBridgeState::peek(*Body::byId(id, scene))) liquid += s->film;
	return liquid > 0 && liquid >= stepFilms->formationThreshold();
}

void Law2_ScGeom_ViscBridgePhys_HertzViscous::reportMissingLiquidEngine()
{
	const std::string msg = "Ip2_FrictMat_FrictMat_ViscBridgePhys.liquidModel='film' needs a ViscBridgeLiquid engine right after the "
	                        "InteractionLoop (it takes the bridges' liquid from the films and gives it back), and O.engines has none "
	                        "(viscbridge.engines(liquidModel='film') inserts it).";
#ifdef YADE_OPENMP
#pragma omp critical(viscbridge_law_step)
#endif
	context->raiseAtNextStep(scene, msg);
}

bool Law2_ScGeom_ViscBridgePhys_HertzViscous::go(shared_ptr<IGeom>& ig, shared_ptr<IPhys>& ip, Interaction* I)
{
	beginStep();
	auto& geom = static_cast<ScGeom&>(*ig);
	auto& ph   = static_cast<ViscBridgePhys&>(*ip);
	return kernels[(ph.kernel * 2 + (scene->trackEnergy ? 1 : 0)) * 2 + (stepImplicit ? 1 : 0)](*this, geom, ph, I);
}

std::string Law2_ScGeom_ViscBridgePhys_HertzViscous::integrationInUseName() const
{
	const Scene* sc = Omega::instance().getScene().get();
	return vb::integrationNames[static_cast<std::size_t>(integrationInUse(sc, integrationIndex))];
}

Real Law2_ScGeom_ViscBridgePhys_HertzViscous::capillaryInput() const
{
	// the work of a step is booked at the next one (E1, physics.md P21: it needs the velocities that
	// followed); the pending step's, F·vn·dt with the velocity it was recorded with, is O(dt²) off
	Scene* sc    = Omega::instance().getScene().get();
	Real   input = -ViscBridgeContext::of(sc).conservativeWork.get();
	for (const auto& I : *sc->interactions) {
		if (!I->isReal()) continue;
		const auto* ph = dynamic_cast<const ViscBridgePhys*>(I->phys.get());
		if (ph && ph->workPending) input += ph->workCapillary * ph->workVn * sc->dt;
	}
	return input;
}

} // namespace yade
