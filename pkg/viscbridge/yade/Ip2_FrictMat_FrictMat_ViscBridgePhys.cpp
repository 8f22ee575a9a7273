#include "viscbridge/yade/Ip2_FrictMat_FrictMat_ViscBridgePhys.hpp"
#include "viscbridge/core/models/Plausible.hpp"
#include "viscbridge/core/models/contact/HertzMindlin.hpp"
#include "viscbridge/core/pair/PairGeometry.hpp"
#include "viscbridge/yade/ViscBridgeState.hpp"
#include <core/Omega.hpp>
#include <core/Scene.hpp>
#include <pkg/common/Sphere.hpp>
#include <pkg/dem/ScGeom.hpp>

namespace yade {

CREATE_LOGGER(Ip2_FrictMat_FrictMat_ViscBridgePhys);

namespace {
	namespace vb = viscbridge;
	const std::string ip2Name = "Ip2_FrictMat_FrictMat_ViscBridgePhys";
	Real              sphereRadius(const Body& b)
	{
		const auto* s = dynamic_cast<const Sphere*>(b.shape.get());
		return s ? s->radius : 0.0;
	}
	Real sphereVolume(Real r) { return 4.0 / 3.0 * vb::pi * r * r * r; }
	bool wettable(const Body& b)
	{
		const ViscBridgeState* s = ViscBridgeState::peek(b);
		return !s || s->wettable;
	}
}

Real& Ip2_FrictMat_FrictMat_ViscBridgePhys::numeric(std::size_t i)
{
	// in the order of parameters::all (checked by its names: a new entry without its attribute throws)
	Real* const members[] = { &viscosity, &bridgeVolume, &bridgeVolumeRel, &contactAngle, &sMin, &sMinRel, &formationDistance, &en, &surfaceTension };
	static_assert(sizeof(members) / sizeof(members[0]) == vb::parameters::all.size(), "one attribute per numeric parameter");
	return *members[i];
}

void Ip2_FrictMat_FrictMat_ViscBridgePhys::validate()
{
	for (std::size_t i = 0; i < vb::parameters::all.size(); ++i)
		vb::parameters::all[i].check(ip2Name, numeric(i));
	vb::ModelSelection s;
	s.normal     = vb::modelIndex<vb::NormalSlot>(ip2Name, normalModel);
	s.tangential = vb::modelIndex<vb::TangentialSlot>(ip2Name, tangentialModel);
	s.capillary  = vb::modelIndex<vb::CapillarySlot>(ip2Name, capillaryModel);
	selection    = s;
	vb::parseName(ip2Name, "liquidModel", liquidModel, vb::liquidModelNames, "liquid model");
}

void Ip2_FrictMat_FrictMat_ViscBridgePhys::postLoad(Ip2_FrictMat_FrictMat_ViscBridgePhys&)
{
	const bool changed = rollback.differs(checked());
	rollback.check(checked(), [&] { validate(); });
	if (changed) {
		warnExistingKeepTheirs();
		warnIneffectiveOrImplausible();
	}
}

void Ip2_FrictMat_FrictMat_ViscBridgePhys::restoreLiquidModel(const std::string& model)
{
	liquidModel = model;
	rollback.check(checked(), [&] { validate(); });
}

void Ip2_FrictMat_FrictMat_ViscBridgePhys::warnIneffectiveOrImplausible() const
{
	if (capillaryModel != vb::CapillaryModels::names[0] && !(surfaceTension > 0))
		LOG_WARN(ip2Name << ".capillaryModel='" << capillaryModel
		                 << "' has no effect while surfaceTension is 0: set surfaceTension [N/m] (water: 0.072) for a capillary force.");
	// the binders of wet granulation (core/models/Plausible.hpp); above them a value in mPa·s is the likely slip
	if (viscosity > 0 && viscosity < vb::plausible::minViscosity)
		LOG_WARN(ip2Name << ".viscosity=" << viscosity << " Pa·s is below " << vb::plausible::minViscosity
		                 << " Pa·s, thinner than any binder (water 1e-3 Pa·s): is the unit right?");
	if (viscosity > vb::plausible::maxViscosity)
		LOG_WARN(ip2Name << ".viscosity=" << viscosity << " Pa·s is above " << vb::plausible::maxViscosity << " Pa·s, the most viscous binders of wet "
		                 << "granulation (detergent pastes): in mPa·s it would be " << viscosity / 1e3 << " Pa·s; viscosity is in Pa·s.");
}

void Ip2_FrictMat_FrictMat_ViscBridgePhys::warnBridgeSize(Real volume, Real particleVolume, Real sRup, Real radius)
{
	// legal, but almost surely a unit mistake (bridgeVolume=0.01 meant as 1 %): said once per Ip2
	if (!(volume > particleVolume || sRup > 2 * radius) || warnedBridgeSize.exchange(true)) return;
	LOG_WARN(ip2Name << ": a bridge of volume " << volume << " m³ (rupture distance " << sRup << " m) between particles of volume "
	                 << particleVolume << " m³ (radius " << radius
	                 << " m) is larger than its particles: bridgeVolume is in m³; for a fraction of the particles' volume use bridgeVolumeRel.");
}

void Ip2_FrictMat_FrictMat_ViscBridgePhys::warnExistingKeepTheirs() const
{
	// A liquid property changed between runs applies to new interactions only: say so, once per change.
	const auto current = Omega::instance().getScene();
	if (!current || current.get() != usedIn) return;
	long existing = 0;
	for (const auto& I : *current->interactions)
		if (I->isReal() && dynamic_cast<const ViscBridgePhys*>(I->phys.get())) ++existing;
	if (existing)
		LOG_WARN(ip2Name << ": the new values apply to interactions created from now on; the " << existing
		                 << " existing ones keep the values they were created with (erase them, e.g. O.interactions.clear(), to rebuild every "
		                    "interaction with the new values).");
}

void Ip2_FrictMat_FrictMat_ViscBridgePhys::go(const shared_ptr<Material>& m1, const shared_ptr<Material>& m2, const shared_ptr<Interaction>& interaction)
{
	if (interaction->phys) return;
	usedIn = scene;
	auto        phys = shared_ptr<ViscBridgePhys>(new ViscBridgePhys());
	const auto  mat1 = YADE_CAST<FrictMat*>(m1.get());
	const auto  mat2 = YADE_CAST<FrictMat*>(m2.get());
	const auto  geom = YADE_CAST<GenericSpheresContact*>(interaction->geom.get());
	const Body& b1   = *Body::byId(interaction->getId1(), scene);
	const Body& b2   = *Body::byId(interaction->getId2(), scene);

	const auto hm = vb::hertzMindlinConstants({ mat1->young, mat1->poisson, mat1->frictionAngle }, { mat2->young, mat2->poisson, mat2->frictionAngle },
	                                          geom->refR1, geom->refR2);
	phys->kno                    = hm.kno;
	phys->kso                    = hm.kso;
	phys->tangensOfFrictionAngle = hm.tanPhi;
	phys->betan = phys->betas = vb::dampingRatioFromRestitution(en);

	phys->radius1 = sphereRadius(b1);
	phys->radius2 = sphereRadius(b2);
	phys->rEff    = vb::reducedRadius(phys->radius1, phys->radius2);
	phys->mEff    = vb::reducedMass(b1.state->mass, b1.isDynamic(), b2.state->mass, b2.isDynamic());

	// the effects this pair has: viscous ones with a viscosity, the capillary one with a surface tension
	vb::ModelSelection s = selection;
	if (!(viscosity > 0)) s.normal = s.tangential = 0;
	if (!(surfaceTension > 0)) s.capillary = 0;
	if (!wettable(b1) || !wettable(b2)) s.normal = s.tangential = s.capillary = 0; // a dry body: a dry contact
	static const std::size_t damped = vb::modelIndex<vb::DampingSlot>(ip2Name, vb::RestitutionContactDamping::name);
	s.damping             = phys->betan > 0 ? damped : 0;
	phys->normalModel     = vb::NormalModels::names[s.normal];
	phys->tangentialModel = vb::TangentialModels::names[s.tangential];
	phys->capillaryModel  = vb::CapillaryModels::names[s.capillary];
	phys->viscosity       = viscosity;
	phys->surfaceTension  = surfaceTension;
	phys->contactAngle    = contactAngle;
	phys->liquidModel     = liquidModel;
	if (bridgeVolume > 0) {
		phys->bridgeVolume = bridgeVolume;
	} else {
		const Real v1      = phys->radius1 > 0 ? sphereVolume(phys->radius1) : sphereVolume(phys->radius2);
		const Real v2      = phys->radius2 > 0 ? sphereVolume(phys->radius2) : sphereVolume(phys->radius1);
		phys->bridgeVolume = bridgeVolumeRel * 0.5 * (v1 + v2);
	}
	phys->sMin              = sMin > 0 ? sMin : sMinRel * phys->rEff;
	phys->sRup              = vb::ruptureDistance(phys->bridgeVolume, contactAngle);
	if (bridgeVolume > 0 && s.normal + s.tangential + s.capillary > 0) {
		const Real r = std::max(phys->radius1, phys->radius2);
		warnBridgeSize(phys->bridgeVolume, sphereVolume(r), phys->sRup, r);
	}
	phys->formationDistance = formationDistance;
	phys->buildConstants(s);
	interaction->phys = phys;
}

} // namespace yade
