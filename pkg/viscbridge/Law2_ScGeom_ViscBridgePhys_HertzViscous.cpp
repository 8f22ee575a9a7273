#include "Law2_ScGeom_ViscBridgePhys_HertzViscous.hpp"
#include "Distributed.hpp"
#include "physics/PairKernel.hpp"
#include "ViscBridgeGuard.hpp"
#include "ViscBridgeImplicitSolver.hpp"
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

	// Books the energy of one step under the keys of the models that have them (physics.md §6).
	template <class Cm, bool E> void bookEnergy(Law2& law, const vb::PairEnergy& e)
	{
		if constexpr (Cm::Capillary::capabilities.enabled) {
			law.capillaryWork += e.capillaryWork;
			if constexpr (E) law.addEnergy(e.capillaryWork, "capillaryWork", law.capillaryWorkIx, false);
		}
		if constexpr (E) {
			if constexpr (Cm::Normal::capabilities.enabled) law.addEnergy(e.dissipNormal, "viscDissipNormal", law.viscDissipNormalIx, false);
			if constexpr (Cm::Tangential::capabilities.enabled) {
				law.addEnergy(e.dissipTangential, "viscDissipTangential", law.viscDissipTangentialIx, false);
				law.addEnergy(e.dissipRotational, "viscDissipRotational", law.viscDissipRotationalIx, false);
			}
			if constexpr (Cm::Damping::capabilities.enabled) law.addEnergy(e.dissipContactDamping, "contactDampDissip", law.contactDampDissipIx, false);
			law.addEnergy(e.dissipFriction, "plastDissip", law.plastDissipIx, false);
			law.addEnergy(e.elasticPotential, "elastPotential", law.elastPotentialIx, true);
		}
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

		vb::PairForces f;
		vb::PairEnergy e;
		[[maybe_unused]] const bool hadBridge = ph.bridge;
		if (!vb::evaluatePair<Cm, E, Imp>(ph.constants, ph, in, f, e)) return false;
		if constexpr (Cm::hasBridge)
			if (!hadBridge && ph.bridge && law.recordFormations) law.noteFormed(id1, id2, ph);
		if constexpr (Imp) ph.implicitBlockIter = scene->iter;
		scene->forces.addForce(id1, f.force1);
		scene->forces.addForce(id2, -f.force1);
		scene->forces.addTorque(id1, f.torque1);
		scene->forces.addTorque(id2, f.torque2);
		// [MPI] an interaction shared by two ranks of yade.mpy is booked by one (always true serially)
		if constexpr (E || Cm::Capillary::capabilities.enabled)
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

void Law2_ScGeom_ViscBridgePhys_HertzViscous::addEnergy(Real value, const char* name, int& index, bool reset)
{
	if (index < 0) {
		// The first lookup registers the name; registration must not race with other threads.
#ifdef YADE_OPENMP
#pragma omp critical(viscbridge_energy_index)
#endif
		scene->energy->add(value, name, index, reset);
		return;
	}
	scene->energy->add(value, name, index, reset);
}

Law2_ScGeom_ViscBridgePhys_HertzViscous::FormedBridge
Law2_ScGeom_ViscBridgePhys_HertzViscous::formedRecord(Body::id_t id1, Body::id_t id2, const ViscBridgePhys& ph)
{
	const Real mobility = ph.mEff > 0 ? 1 / ph.mEff : 0;
	return { id1, id2, ph.viscousStepCoefficient * mobility, ph.capillaryStiffness * mobility };
}

void Law2_ScGeom_ViscBridgePhys_HertzViscous::noteFormed(Body::id_t id1, Body::id_t id2, const ViscBridgePhys& ph)
{
	const FormedBridge record = formedRecord(id1, id2, ph);
	// rare (a formation), so a critical section costs nothing that matters
#ifdef YADE_OPENMP
#pragma omp critical(viscbridge_formed)
#endif
	formed.push_back(record);
}

std::vector<Law2_ScGeom_ViscBridgePhys_HertzViscous::FormedBridge> Law2_ScGeom_ViscBridgePhys_HertzViscous::takeFormed()
{
	std::vector<FormedBridge> out;
	out.swap(formed);
	return out;
}

void Law2_ScGeom_ViscBridgePhys_HertzViscous::postLoad(Law2_ScGeom_ViscBridgePhys_HertzViscous&)
{
	static const std::string name = "Law2_ScGeom_ViscBridgePhys_HertzViscous";
	try {
		integrationIndex = static_cast<int>(viscbridge::parseName(name, "integration", integration, viscbridge::integrationNames));
	} catch (const std::invalid_argument&) {
		integration = lastValidIntegration;
		throw;
	}
	lastValidIntegration = integration;
}

bool Law2_ScGeom_ViscBridgePhys_HertzViscous::solverPresent()
{
	// Looked up once per step (the first interaction of the step does it, the others wait).
	if (solverCheckedIter.load(std::memory_order_acquire) == scene->iter) return solverFound;
#ifdef YADE_OPENMP
#pragma omp critical(viscbridge_solver_lookup)
#endif
	{
		if (solverCheckedIter.load(std::memory_order_relaxed) != scene->iter) {
			solverFound = false;
			for (const auto& e : scene->engines)
				if (dynamic_cast<const ViscBridgeImplicitSolver*>(e.get())) solverFound = true;
			if (!solverFound) reportMissingSolver();
			solverCheckedIter.store(scene->iter, std::memory_order_release);
		}
	}
	return solverFound;
}

void Law2_ScGeom_ViscBridgePhys_HertzViscous::reportMissingSolver()
{
	// Exceptions cannot leave InteractionLoop's parallel loop, so the error is raised by a
	// ViscBridgeGuard at the start of the next step (this step falls back to explicit forces).
	const std::string msg = "Law2_ScGeom_ViscBridgePhys_HertzViscous.integration='implicit' needs a ViscBridgeImplicitSolver engine between "
	                        "InteractionLoop and NewtonIntegrator, and O.engines has none (viscbridge.engines(integration='implicit') inserts it).";
	LOG_ERROR(msg << " This step used explicit viscous forces; the run stops.");
	ViscBridgeGuard::raiseAtNextStep(scene, msg);
}

bool Law2_ScGeom_ViscBridgePhys_HertzViscous::go(shared_ptr<IGeom>& ig, shared_ptr<IPhys>& ip, Interaction* I)
{
	auto&      geom     = static_cast<ScGeom&>(*ig);
	auto&      ph       = static_cast<ViscBridgePhys&>(*ip);
	const bool implicit = integrationIndex == static_cast<int>(viscbridge::Integration::implicitEuler) && solverPresent();
	return kernels[(ph.kernel * 2 + (scene->trackEnergy ? 1 : 0)) * 2 + (implicit ? 1 : 0)](*this, geom, ph, I);
}

Real Law2_ScGeom_ViscBridgePhys_HertzViscous::capillaryInput() const
{
	// the work of a step is booked at the next one (E1, physics.md P21: it needs the velocities that
	// followed); the pending step's, F·vn·dt with the velocity it was recorded with, is O(dt²) off
	const Scene* sc    = Omega::instance().getScene().get();
	Real         input = -capillaryWork.get();
	for (const auto& I : *sc->interactions) {
		if (!I->isReal()) continue;
		const auto* ph = dynamic_cast<const ViscBridgePhys*>(I->phys.get());
		if (ph && ph->workPending) input += ph->workCapillary * ph->workVn * sc->dt;
	}
	return input;
}

} // namespace yade
