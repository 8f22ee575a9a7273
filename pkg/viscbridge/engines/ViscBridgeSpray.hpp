// ViscBridgeSpray: binder sprayed onto the particles during a run (physics.md §11, L6, L7).  Every
// period it adds what its nozzle sprayed since the last call to the liquid it holds (`pending`) and
// gives that to the spheres in its zone that the spray reaches — the bed's surface seen from the
// nozzle, recomputed as the bed moves — in proportion to the area each shows the nozzle, no film
// beyond maxFilmRel of its sphere's volume.  Everything it needs to go on is an attribute, so a
// spray saved with the scene continues after O.load in a new process, nothing sprayed twice.
#pragma once
#include "viscbridge/core/liquid/SprayDeposit.hpp"
#include "viscbridge/yade/AttributeRollback.hpp"
#include <pkg/common/PeriodicEngines.hpp>
#include <vector>

namespace yade {

class ViscBridgeSpray : public PeriodicEngine {
	AttributeRollback<Real, Real, Real, Real, Real, Vector3r, Real> rollback;
	auto checked() { return std::tie(rate, start, end, maxFilmRel, ballRadius, nozzle, dropletVolume); }
	viscbridge::SprayShadow shadow; // its buffers, kept between calls
	std::vector<viscbridge::Vec3> centres;
	std::vector<double>           radii, weight, room, given;
	std::vector<Body::id_t>       ids;
	bool                          warnedUnreached = false, warnedFull = false, warnedAfterEnd = false;

	void checkZone() const;
	bool inZone(const Vector3r& x) const;
	void accountSprayed(Real now);
	void collectTargets();
	void weigh();
	void deliver(bool windowOver);
	void warnOnce(bool& warned, const std::string& what);
	std::string zoneText() const;

public:
	void action() override;
	void postLoad(ViscBridgeSpray&);
	// clang-format off
	YADE_CLASS_BASE_DOC_ATTRS_CTOR(ViscBridgeSpray, PeriodicEngine,
		"Sprays binder onto the particles during a run, for ``liquidModel='film'`` (physics.md §11, L6 and L7; made by "
		":yref:`viscbridge.liquid.spray()` and ``Drum.spray()``, which also check every argument). Every period "
		"(iterPeriod, virtPeriod, as any :yref:`PeriodicEngine`) it counts what the nozzle sprayed since its last call — "
		"rate × the time of the spray window [start, end] that elapsed — and gives it to the spheres whose centre is in "
		"its zone (the box boxMin–boxMax, or the ball of ballRadius about ballCentre) and that the spray reaches: "
		"droplets travel along ``nozzle`` and wet the first sphere they meet, so each sphere takes in proportion to the "
		"area it shows the nozzle that no other sphere of the zone hides (the bed's free surface, recomputed as the bed "
		"moves; L6) — shared as a mist, or as whole droplets of dropletVolume each landing on one sphere (L6b). No film grows beyond maxFilmRel × its sphere's volume: what a full sphere cannot take goes to the "
		"other reached spheres, and when they are all full it stays ``pending`` until there is room (L7). Liquid "
		"sprayed while no sphere is reached waits in ``pending`` too, and goes to the first spheres reached, also after "
		"``end`` — YADE's log says so, once. Spheres made dry (:yref:`ViscBridgeState.wettable` False) hide what is "
		"below them and take nothing; walls and facets neither hide nor take. The total liquid of the scene grows by "
		"exactly ``delivered``. Every quantity it goes on with is an attribute: saved with the scene, it continues "
		"after O.load, nothing sprayed twice. Refused under yade.mpy.",
		((Real,rate,0,Attr::triggerPostLoad,"Binder the nozzle sprays [m³/s], >= 0."))
		((Real,start,0,Attr::triggerPostLoad,"Simulated time the spray starts [s], >= 0."))
		((Real,end,-1,Attr::triggerPostLoad,"Simulated time the spray stops [s], > start; < 0: it never stops."))
		((Vector3r,boxMin,Vector3r::Zero(),,"Lower corner of the box zone [m] (used when ballRadius is 0)."))
		((Vector3r,boxMax,Vector3r::Zero(),,"Upper corner of the box zone [m], >= boxMin in every axis."))
		((Vector3r,ballCentre,Vector3r::Zero(),,"Centre of the ball zone [m]."))
		((Real,ballRadius,0,Attr::triggerPostLoad,"Radius of the ball zone [m], >= 0; 0: the zone is the box."))
		((Vector3r,nozzle,Vector3r(0,0,-1),Attr::triggerPostLoad,"The direction the droplets travel (any length). Zero: no shadow — every sphere in the zone takes in proportion to its cross-section, hidden or not."))
		((Real,maxFilmRel,0.1,Attr::triggerPostLoad,"The largest film the spray builds on a sphere, as a fraction of the sphere's volume, > 0 (L7)."))
		((Real,dropletVolume,0,Attr::triggerPostLoad,"Volume of one droplet [m³], >= 0. 0: a fine mist — every reached sphere takes its share at each call (L6). Above 0: whole droplets, each landing on one reached sphere drawn with probability in proportion to the area it shows the nozzle, among those it fits on (L6b); less than a droplet waits in pending (after ``end``, it lands as a last smaller droplet). Droplets near a particle's size wet spots that nucleate granules; a mist wets the whole surface."))
		((long,seed,0,,"Seed of the droplets' draws: droplet k lands where it does from (seed, k) alone, in any run that reaches it (saved, resumed, any number of threads)."))
		((long,droplets,0,Attr::readonly,"Droplets landed so far (with dropletVolume > 0)."))
		((Real,sprayed,0,Attr::readonly,"Liquid the nozzle has sprayed so far [m³] (delivered + pending)."))
		((Real,delivered,0,Attr::readonly,"Liquid put into the particles' films so far [m³]."))
		((Real,pending,0,Attr::readonly,"Liquid sprayed and not yet in a film [m³]: no sphere was reached, or all were full."))
		((Real,accountedUntil,-1,Attr::readonly,"Simulated time up to which the nozzle's output is counted [s] (-1: not yet)."))
		((int,receivers,0,Attr::readonly,"Spheres that took liquid at the last call."))
		,
		/* ctor */ rollback.keep(checked());
	);
	// clang-format on
	DECLARE_LOGGER;
};
REGISTER_SERIALIZABLE(ViscBridgeSpray);

} // namespace yade
