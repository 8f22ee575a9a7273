#include "viscbridge/yade/ViscBridgePhys.hpp"
#include "viscbridge/core/liquid/FilmExchange.hpp"

namespace yade {

viscbridge::BridgeInputs ViscBridgePhys::bridgeInputs() const
{
	viscbridge::BridgeInputs in;
	in.viscosity      = viscosity;
	in.rBar           = rEff;
	in.radius1        = radius1;
	in.radius2        = radius2;
	in.mEff           = mEff;
	in.volume         = bridgeVolume;
	in.sMin           = sMin;
	in.sRup           = sRup;
	in.contactAngle   = contactAngle;
	in.surfaceTension = surfaceTension;
	in.dampingRatio   = betan;
	return in;
}

void ViscBridgePhys::buildConstants(const viscbridge::ModelSelection& s)
{
	selection              = s;
	constants              = viscbridge::makePairConstants(s, { kno, kso, tangensOfFrictionAngle }, bridgeInputs(), formationDistance);
	constants.fromFilms    = liquidModel == viscbridge::liquidModelNames[static_cast<int>(viscbridge::LiquidModel::film)];
	kernel                 = viscbridge::comboIndex(s);
	viscousStepCoefficient = constants.viscousStepCoefficient;
	capillaryStiffness     = constants.capillaryStiffness;
}

void ViscBridgePhys::postLoad(ViscBridgePhys&)
{
	namespace vb      = viscbridge;
	const char* owner = "ViscBridgePhys";
	vb::ModelSelection s;
	s.normal     = vb::modelIndex<vb::NormalSlot>(owner, normalModel);
	s.tangential = vb::modelIndex<vb::TangentialSlot>(owner, tangentialModel);
	s.capillary  = vb::modelIndex<vb::CapillarySlot>(owner, capillaryModel);
	s.damping    = vb::modelIndex<vb::DampingSlot>(owner, betan > 0 || betas > 0 ? vb::RestitutionContactDamping::name : vb::NoContactDamping::name);
	buildConstants(s);
}

} // namespace yade
