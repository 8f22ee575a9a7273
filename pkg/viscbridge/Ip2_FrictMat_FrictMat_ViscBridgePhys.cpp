#include "Ip2_FrictMat_FrictMat_ViscBridgePhys.hpp"
#include "physics/HertzMindlin.hpp"
#include "physics/ModelNames.hpp"
#include "physics/PairGeometry.hpp"
#include "physics/TimeStepBounds.hpp"
#include "physics/Validation.hpp"
#include <core/Scene.hpp>
#include <pkg/common/Sphere.hpp>
#include <pkg/dem/ScGeom.hpp>

namespace yade {

CREATE_LOGGER(Ip2_FrictMat_FrictMat_ViscBridgePhys);

namespace {
	const std::string ip2Name = "Ip2_FrictMat_FrictMat_ViscBridgePhys";
	Real              sphereRadius(const Body& b)
	{
		const auto* s = dynamic_cast<const Sphere*>(b.shape.get());
		return s ? s->radius : 0.0;
	}
	Real sphereVolume(Real r) { return 4.0 / 3.0 * viscbridge::pi * r * r * r; }
}

Ip2_FrictMat_FrictMat_ViscBridgePhys::Parameters Ip2_FrictMat_FrictMat_ViscBridgePhys::current() const
{
	return { viscosity, bridgeVolume, bridgeVolumeRel, contactAngle, sMin, sMinRel, formationDistance, en, normalModel, tangentialModel };
}

void Ip2_FrictMat_FrictMat_ViscBridgePhys::restore(const Parameters& p)
{
	viscosity         = p.viscosity;
	bridgeVolume      = p.bridgeVolume;
	bridgeVolumeRel   = p.bridgeVolumeRel;
	contactAngle      = p.contactAngle;
	sMin              = p.sMin;
	sMinRel           = p.sMinRel;
	formationDistance = p.formationDistance;
	en                = p.en;
	normalModel       = p.normalModel;
	tangentialModel   = p.tangentialModel;
}

void Ip2_FrictMat_FrictMat_ViscBridgePhys::validate()
{
	using namespace viscbridge;
	requireNonNegative(ip2Name, "viscosity", viscosity, " [Pa·s]; 0 means dry");
	requireNonNegative(ip2Name, "bridgeVolume", bridgeVolume, " [m³]; 0 means bridgeVolumeRel times the particle volume");
	requireInRange(ip2Name, "bridgeVolumeRel", bridgeVolumeRel, 0, true, 1, false);
	requireInRange(ip2Name, "contactAngle", contactAngle, 0, false, pi / 2, false);
	requireNonNegative(ip2Name, "sMin", sMin, " [m]; 0 means sMinRel times the reduced radius");
	requireInRange(ip2Name, "sMinRel", sMinRel, 0, true, 1, false);
	requireNonNegative(ip2Name, "formationDistance", formationDistance, " [m]; 0 means at contact");
	requireInRange(ip2Name, "en", en, 0, true, 1, false);
	normalModelIndex     = parseName(ip2Name, "normalModel", normalModel, normalModelNames);
	tangentialModelIndex = parseName(ip2Name, "tangentialModel", tangentialModel, tangentialModelNames);
}

void Ip2_FrictMat_FrictMat_ViscBridgePhys::postLoad(Ip2_FrictMat_FrictMat_ViscBridgePhys&)
{
	try {
		validate();
	} catch (const std::invalid_argument&) {
		restore(lastValid);
		validate();
		throw;
	}
	lastValid = current();
}

void Ip2_FrictMat_FrictMat_ViscBridgePhys::go(const shared_ptr<Material>& m1, const shared_ptr<Material>& m2, const shared_ptr<Interaction>& interaction)
{
	if (interaction->phys) return;
	auto       phys = shared_ptr<ViscBridgePhys>(new ViscBridgePhys());
	const auto mat1 = YADE_CAST<FrictMat*>(m1.get());
	const auto mat2 = YADE_CAST<FrictMat*>(m2.get());
	const auto geom = YADE_CAST<GenericSpheresContact*>(interaction->geom.get());
	const Body& b1  = *Body::byId(interaction->getId1(), scene);
	const Body& b2  = *Body::byId(interaction->getId2(), scene);

	const auto hm = viscbridge::hertzMindlinConstants({ mat1->young, mat1->poisson, mat1->frictionAngle },
	                                                  { mat2->young, mat2->poisson, mat2->frictionAngle }, geom->refR1, geom->refR2);
	phys->kno                    = hm.kno;
	phys->kso                    = hm.kso;
	phys->tangensOfFrictionAngle = hm.tanPhi;
	phys->betan = phys->betas = viscbridge::dampingRatioFromRestitution(en);

	phys->radius1 = sphereRadius(b1);
	phys->radius2 = sphereRadius(b2);
	phys->rEff    = viscbridge::reducedRadius(phys->radius1, phys->radius2);
	phys->mEff    = viscbridge::reducedMass(b1.state->mass, b1.isDynamic(), b2.state->mass, b2.isDynamic());

	const bool wet         = viscosity > 0;
	phys->normalModel      = wet ? normalModelIndex : 0;
	phys->tangentialModel  = wet ? tangentialModelIndex : 0;
	phys->viscosity        = viscosity;
	if (bridgeVolume > 0) {
		phys->bridgeVolume = bridgeVolume;
	} else {
		const Real v1 = phys->radius1 > 0 ? sphereVolume(phys->radius1) : sphereVolume(phys->radius2);
		const Real v2 = phys->radius2 > 0 ? sphereVolume(phys->radius2) : sphereVolume(phys->radius1);
		phys->bridgeVolume = bridgeVolumeRel * 0.5 * (v1 + v2);
	}
	phys->sMin              = sMin > 0 ? sMin : sMinRel * phys->rEff;
	phys->sRup              = viscbridge::ruptureDistance(phys->bridgeVolume, contactAngle);
	phys->formationDistance = formationDistance;
	phys->viscousStepCoefficient = viscbridge::viscousStepCoefficient(
	        static_cast<viscbridge::NormalModel>(phys->normalModel), static_cast<viscbridge::TangentialModel>(phys->tangentialModel),
	        phys->viscosity, phys->rEff, phys->bridgeVolume, phys->sMin, phys->radius1, phys->radius2);
	interaction->phys = phys;
}

} // namespace yade
