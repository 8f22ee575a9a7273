#include "Law2_ScGeom_ViscBridgePhys_HertzViscous.hpp"
#include "Distributed.hpp"
#include "physics/ModelNames.hpp"
#include "physics/PairKernel.hpp"
#include "ViscBridgeGuard.hpp"
#include "ViscBridgeImplicitSolver.hpp"
#include <core/Scene.hpp>
#include <array>
#include <tuple>
#include <utility>

namespace yade {

CREATE_LOGGER(Law2_ScGeom_ViscBridgePhys_HertzViscous);

namespace {
	using Law2 = Law2_ScGeom_ViscBridgePhys_HertzViscous;
	namespace vb = viscbridge;

	// The sub-models in the order of their names in physics/ModelNames.hpp.
	using NormalModels     = std::tuple<vb::NoNormalViscous, vb::AdamsPerchard, vb::Pitois>;
	using TangentialModels = std::tuple<vb::NoTangentialViscous, vb::WashinoTangential, vb::SlipTangential, vb::GoldmanTangential>;
	using DampingModels    = std::tuple<vb::NoContactDamping, vb::RestitutionContactDamping>;
	constexpr std::size_t nNormal = std::tuple_size_v<NormalModels>, nTangential = std::tuple_size_v<TangentialModels>,
	                      nDamping = std::tuple_size_v<DampingModels>;

	// Each sub-model's parameters, from the interaction's physics.
	template <class M> M makeModel(const ViscBridgePhys&) { return M {}; }
	template <> vb::AdamsPerchard makeModel(const ViscBridgePhys& p) { return vb::AdamsPerchard(p.viscosity, p.rEff); }
	template <> vb::Pitois        makeModel(const ViscBridgePhys& p) { return vb::Pitois(p.viscosity, p.rEff, p.bridgeVolume); }
	template <> vb::WashinoTangential makeModel(const ViscBridgePhys& p) { return vb::WashinoTangential(p.viscosity, p.rEff); }
	template <> vb::SlipTangential    makeModel(const ViscBridgePhys& p) { return vb::SlipTangential(p.viscosity, p.rEff); }
	template <> vb::GoldmanTangential makeModel(const ViscBridgePhys& p) { return vb::GoldmanTangential(p.viscosity, p.rEff); }
	template <> vb::RestitutionContactDamping makeModel(const ViscBridgePhys& p) { return vb::RestitutionContactDamping { p.betan, p.betas }; }

	using Kernel = bool (*)(Law2&, ScGeom&, ViscBridgePhys&, Interaction*);

	// One interaction step with the models N, T, D fixed at compile time; E: track energy;
	// Imp: leave the viscous forces to ViscBridgeImplicitSolver (describe them in the physics).
	template <class N, class T, class D, bool E, bool Imp> bool lawKernel(Law2& law, ScGeom& geom, ViscBridgePhys& ph, Interaction* I)
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
		if constexpr (D::enabled) in.contactRelVel = geom.getIncidentVel(s1, s2, scene->dt, shift2, shiftVel, /*avoidGranularRatcheting*/ false);
		else in.contactRelVel = Vector3r::Zero();
		in.shearIncrement = geom.shearIncrement();
		in.dt             = scene->dt;

		vb::PairState st;
		st.shearElastic   = geom.rotate(ph.shearElastic);
		st.shearPotential = ph.shearPotential;
		st.bridge         = ph.bridge;
		if constexpr (E) st.lastViscous = { ph.workPending, ph.workCn, ph.workVn, ph.workU, ph.workS, { ph.workM1[0], ph.workM1[1], ph.workM2[0], ph.workM2[1] } };

		const vb::PairModels<N, T, D> models { makeModel<N>(ph), makeModel<T>(ph), makeModel<D>(ph) };
		const vb::PairParams          params { { ph.kno, ph.kso, ph.tangensOfFrictionAngle }, ph.mEff, ph.sMin, ph.sRup, ph.formationDistance };
		vb::PairOutput                out;
		const bool                    keep = vb::evaluatePair<E, Imp>(models, params, st, in, out);
		ph.bridge                          = st.bridge;
		ph.separation                      = in.S;
		if constexpr (E) {
			const vb::ViscousWorkRecord& w = st.lastViscous;
			ph.workPending                 = w.pending;
			ph.workCn                      = w.cn;
			ph.workVn                      = w.vn;
			ph.workU                       = w.u;
			ph.workS                       = w.s;
			ph.workM1                      = Vector2r(w.resistance.m11, w.resistance.m12);
			ph.workM2                      = Vector2r(w.resistance.m21, w.resistance.m22);
		} else {
			ph.workPending = false; // work is only accounted between two tracked steps
		}
		if (!keep) return false;

		ph.shearElastic       = st.shearElastic;
		ph.shearPotential     = st.shearPotential;
		ph.kn                 = out.kn;
		ph.ks                 = out.ks;
		ph.cn                 = out.cn;
		ph.ct                 = out.ct;
		ph.cr                 = out.cr;
		ph.normalContactForce = out.normalContact;
		ph.shearContactForce  = out.shearContact;
		ph.normalViscousForce = out.normalViscous;
		ph.shearViscousForce  = out.shearViscous;
		if constexpr (Imp) {
			// the solver sets the viscous forces from the implicit velocities, later in this step
			ph.implicitBlock      = out.block;
			ph.implicitBlockIter  = scene->iter;
			ph.normalViscousForce = ph.shearViscousForce = Vector3r::Zero();
			ph.normalForce        = -out.normalContact; // YADE sense: sustained by body 2
			ph.shearForce         = -out.shearContact;
		} else {
			ph.normalForce = -(out.normalContact + out.normalViscous);
			ph.shearForce  = -(out.shearContact + out.shearViscous);
		}

		scene->forces.addForce(id1, out.force1);
		scene->forces.addForce(id2, -out.force1);
		scene->forces.addTorque(id1, out.torque1);
		scene->forces.addTorque(id2, out.torque2);

		if constexpr (E) {
			// [MPI] an interaction shared by two ranks of yade.mpy is booked by one (always true serially)
			if (!distributed::ownershipThisStep(scene).interaction(*I, scene)) return true;
			if constexpr (N::enabled) law.addEnergy(out.dissipNormal, "viscDissipNormal", law.viscDissipNormalIx, false);
			if constexpr (T::enabled) {
				law.addEnergy(out.dissipTangential, "viscDissipTangential", law.viscDissipTangentialIx, false);
				law.addEnergy(out.dissipRotational, "viscDissipRotational", law.viscDissipRotationalIx, false);
			}
			if constexpr (D::enabled) law.addEnergy(out.dissipContactDamping, "contactDampDissip", law.contactDampDissipIx, false);
			law.addEnergy(out.dissipFriction, "plastDissip", law.plastDissipIx, false);
			law.addEnergy(out.elasticPotential, "elastPotential", law.elastPotentialIx, true);
		}
		return true;
	}

	template <bool Imp, std::size_t K> constexpr Kernel kernelAt()
	{
		constexpr std::size_t e = K % 2, d = (K / 2) % nDamping, t = (K / (2 * nDamping)) % nTangential, n = K / (2 * nDamping * nTangential);
		return &lawKernel<std::tuple_element_t<n, NormalModels>, std::tuple_element_t<t, TangentialModels>, std::tuple_element_t<d, DampingModels>, e == 1, Imp>;
	}
	template <bool Imp, std::size_t... K> constexpr std::array<Kernel, sizeof...(K)> makeKernelTable(std::index_sequence<K...>)
	{
		return { kernelAt<Imp, K>()... };
	}
	constexpr std::size_t nKernels        = nNormal * nTangential * nDamping * 2;
	constexpr auto        explicitKernels = makeKernelTable<false>(std::make_index_sequence<nKernels>());
	constexpr auto        implicitKernels = makeKernelTable<true>(std::make_index_sequence<nKernels>());

	inline std::size_t kernelIndex(const ViscBridgePhys& ph, bool trackEnergy)
	{
		const std::size_t damping = (ph.betan > 0 || ph.betas > 0) ? 1 : 0;
		return ((static_cast<std::size_t>(ph.normalModel) * nTangential + static_cast<std::size_t>(ph.tangentialModel)) * nDamping + damping) * 2
		        + (trackEnergy ? 1 : 0);
	}
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

void Law2_ScGeom_ViscBridgePhys_HertzViscous::postLoad(Law2_ScGeom_ViscBridgePhys_HertzViscous&)
{
	static const std::string name = "Law2_ScGeom_ViscBridgePhys_HertzViscous";
	try {
		integrationIndex = viscbridge::parseName(name, "integration", integration, viscbridge::integrationNames);
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
	auto&             geom = static_cast<ScGeom&>(*ig);
	auto&             ph   = static_cast<ViscBridgePhys&>(*ip);
	const std::size_t k    = kernelIndex(ph, scene->trackEnergy);
	if (integrationIndex == static_cast<int>(viscbridge::Integration::implicitEuler) && solverPresent()) return implicitKernels[k](*this, geom, ph, I);
	return explicitKernels[k](*this, geom, ph, I);
}

} // namespace yade
