// viscbridge_registry: what the C++ side knows, written for the Python side (no YADE needed).
//
//   viscbridge_registry --python   the module py/viscbridge/_registry.py: slots, model names,
//                                  capabilities, energy keys, the Ip2's numeric parameters
//   viscbridge_registry --golden   JSON lines of coefficients and bounds of the C++ kernels on a grid
//                                  of inputs, which tests/unit/test_criteria.py compares with
//                                  viscbridge.criteria (one formula source: the kernels)
#include "viscbridge/core/models/Parameters.hpp"
#include "viscbridge/core/models/Plausible.hpp"
#include "viscbridge/core/models/contact/HertzMindlin.hpp"
#include "viscbridge/core/pair/PairConstants.hpp"
#include "viscbridge/core/pair/PairGeometry.hpp"
#include "viscbridge/core/pair/PairRecord.hpp"
#include <boost/preprocessor/stringize.hpp>
#include "viscbridge/core/timestep/TimeStepBounds.hpp"
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

namespace vb = viscbridge;

namespace {

std::string quoted(const char* s) { return std::string("'") + s + "'"; }
std::string number(double v)
{
	if (v == std::numeric_limits<double>::infinity()) return "math.inf";
	char buf[40];
	std::snprintf(buf, sizeof buf, "%.17g", v);
	std::string text = buf;
	if (text.find_first_of(".e") == std::string::npos) text += ".0"; // a float in Python too
	return text;
}

// A Python string literal of any text (backslashes and quotes escaped).
std::string pyString(const char* text)
{
	std::string out = "'";
	for (const char* c = text; *c; ++c) {
		if (*c == '\\' || *c == '\'') out += '\\';
		out += *c;
	}
	return out + "'";
}

// The flags of the record's attribute tuples, as YADE's Attr (only which kind: output or internal).
namespace Attr {
	enum : int { noSave = 1, readonly = 2, triggerPostLoad = 4, hidden = 8 };
}
void printRecordEntry(const char* type, const char* name, bool output, const char* doc)
{
	std::printf("    %s: dict(type=%s, output=%s, doc=%s),\n", quoted(name).c_str(), quoted(type).c_str(), output ? "True" : "False", pyString(doc).c_str());
}
#define VISCBRIDGE_PRINT_RECORD(r, data, attr)                                                                                                   \
	printRecordEntry(BOOST_PP_STRINGIZE(BOOST_PP_TUPLE_ELEM(5, 0, attr)), BOOST_PP_STRINGIZE(BOOST_PP_TUPLE_ELEM(5, 1, attr)),                \
	                 ((BOOST_PP_TUPLE_ELEM(5, 3, attr)) & Attr::readonly) != 0, BOOST_PP_TUPLE_ELEM(5, 4, attr));

template <class M> void printKeys()
{
	std::string keys;
	for (const vb::EnergyKey k : M::energyKeys)
		keys += (keys.empty() ? "" : ", ") + quoted(vb::spec(k).name);
	if (M::energyKeys.size() == 1) keys += ",";
	std::printf("            %s: (%s),\n", quoted(M::name).c_str(), keys.c_str());
}
template <class L, std::size_t... I> void printEnergyKeys(std::index_sequence<I...>) { (printKeys<typename L::template At<I>>(), ...); }

template <class S> void printSlot()
{
	using L = typename S::Models;
	std::printf("    %s: dict(\n        default=%s,\n        description=%s,\n        models=(", quoted(S::parameter).c_str(),
	            quoted(S::defaultModel).c_str(), quoted(S::description).c_str());
	for (std::size_t i = 0; i < L::size; ++i)
		std::printf("%s%s", quoted(L::names[i]).c_str(), i + 1 < L::size ? ", " : "");
	std::printf("),\n        capabilities={\n");
	for (std::size_t i = 0; i < L::size; ++i) {
		const vb::Capabilities& c = L::capabilities[i];
		std::printf("            %s: dict(enabled=%s, dissipative=%s, conservative=%s, beyondContact=%s, implicitCapable=%s),\n",
		            quoted(L::names[i]).c_str(), c.enabled ? "True" : "False", c.dissipative ? "True" : "False", c.conservative ? "True" : "False",
		            c.beyondContact ? "True" : "False", c.implicitCapable ? "True" : "False");
	}
	std::printf("        },\n        energyKeys={\n");
	printEnergyKeys<L>(std::make_index_sequence<L::size>());
	std::printf("        }),\n");
}

void printPython()
{
	std::printf("\"\"\"What the C++ side of ViscBridge registers, for the Python tools (generated: do not edit).\n\n"
	            "Made by `viscbridge_registry --python` from pkg/viscbridge/core/models/Registry.hpp,\n"
	            "Parameters.hpp and core/pair/PairRecord.hpp; tests/unit/test_registry.py fails when it is out of date.\n\"\"\"\n");
	std::printf("import math\n\n");
	std::printf("#: The slots of a wet contact: the Ip2 attribute that selects the model, its models in order\n");
	std::printf("#: (the first is 'none'), their capabilities and the O.energy keys each books.\n");
	std::printf("SLOTS = {\n");
	printSlot<vb::NormalSlot>();
	printSlot<vb::TangentialSlot>();
	printSlot<vb::DampingSlot>();
	printSlot<vb::CapillarySlot>();
	std::printf("}\n\n#: The time integrations of the viscous forces (Law2_ScGeom_ViscBridgePhys_HertzViscous.integration).\n");
	std::printf("INTEGRATIONS = (%s, %s)\n\n", quoted(vb::integrationNames[0]).c_str(), quoted(vb::integrationNames[1]).c_str());
	std::printf("#: Beyond these a value is legal but almost surely a unit mistake (core/models/Plausible.hpp).\n");
	std::printf("PLAUSIBLE = dict(maxRadius=%s, minViscosity=%s, maxViscosity=%s)\n\n", number(vb::plausible::maxRadius).c_str(),
	            number(vb::plausible::minViscosity).c_str(), number(vb::plausible::maxViscosity).c_str());
	std::printf("#: The numeric parameters of Ip2_FrictMat_FrictMat_ViscBridgePhys: unit, default, allowed range.\n");
	std::printf("PARAMETERS = {\n");
	for (const vb::ParameterSpec& p : vb::parameters::all)
		std::printf("    %s: dict(unit=%s, default=%s, lo=%s, hi=%s, lo_open=%s, hi_open=%s, zero_means=%s),\n", quoted(p.name).c_str(),
		            quoted(p.unit).c_str(), number(p.defaultValue).c_str(), number(p.lo).c_str(), number(p.hi).c_str(), p.loOpen ? "True" : "False",
		            p.hiOpen ? "True" : "False", quoted(p.zeroMeans).c_str());
	std::printf("}\n\n#: The per-contact record of ViscBridgePhys (core/pair/PairRecord.hpp), in its order: the type of each\n");
	std::printf("#: attribute, whether it is an output a user reads (else internal state), and its documentation.\n");
	std::printf("RECORD = {\n");
	BOOST_PP_SEQ_FOR_EACH(VISCBRIDGE_PRINT_RECORD, ~, VISCBRIDGE_PAIR_RECORD_ATTRS)
	std::printf("}\n");
}

// One line of golden data: {"q": quantity, "in": {...}, "v": value}.
void golden(const char* quantity, const std::string& inputs, double value)
{
	char v[40];
	if (std::isinf(value)) std::snprintf(v, sizeof v, "%sInfinity", value < 0 ? "-" : ""); // as Python's json writes it
	else std::snprintf(v, sizeof v, "%.17g", value);
	std::printf("{\"q\": \"%s\", \"in\": {%s}, \"v\": %s}\n", quantity, inputs.c_str(), v);
}
std::string kv(const char* k, double v)
{
	char buf[80];
	std::snprintf(buf, sizeof buf, "\"%s\": %.17g", k, v);
	return buf;
}
std::string ks(const char* k, const char* v) { return std::string("\"") + k + "\": \"" + v + "\""; }

void printGolden()
{
	const double radii[] = { 5e-4, 2e-4, 1e-3 };
	const double viscosities[] = { 1e-3, 1.0, 1000.0 };
	const double gaps[] = { 1e-9, 3e-7, 1e-5, 2e-4 };
	for (double r1 : radii)
		for (double r2 : { 0.0, 5e-4, 1e-3 }) { // 0: a wall
			const double rBar = vb::reducedRadius(r1, r2), V = 0.01 * 4.0 / 3.0 * vb::pi * r1 * r1 * r1;
			for (double mu : viscosities)
				for (double S : gaps) {
					const std::string in = kv("r1", r1) + ", " + kv("r2", r2) + ", " + kv("mu", mu) + ", " + kv("S", S) + ", " + kv("V", V);
					golden("adamsPerchard", in, vb::AdamsPerchard(mu, rBar).coefficient(S));
					golden("pitois", in, vb::Pitois(mu, rBar, V).coefficient(S));
					golden("pitoisFactor", in, vb::Pitois(mu, rBar, V).volumeFactor(S));
					const vb::GoldmanCoefficients g = vb::goldmanCoefficients(6 * vb::pi * mu * rBar, rBar, S);
					golden("C_T", in, g.translation);
					golden("C_R", in, g.coupling);
					golden("C_W", in, g.rotation);
				}
			for (const char* normal : vb::NormalModels::names)
				for (const char* tangential : vb::TangentialModels::names)
					for (double sMinRel : { 1e-4, 1e-2 }) {
						vb::BridgeInputs b;
						b.viscosity = 1.0, b.rBar = rBar, b.radius1 = r1, b.radius2 = r2, b.volume = V, b.sMin = sMinRel * rBar;
						vb::ModelSelection s;
						s.normal     = vb::modelIndex<vb::NormalSlot>("golden", normal);
						s.tangential = vb::modelIndex<vb::TangentialSlot>("golden", tangential);
						const vb::PairConstants k = vb::makePairConstants(s, {}, b, 0);
						golden("viscousStepCoefficient",
						       kv("r1", r1) + ", " + kv("r2", r2) + ", " + kv("sMin", b.sMin) + ", " + kv("V", V) + ", " + ks("normal", normal) + ", "
						               + ks("tangential", tangential),
						       k.viscousStepCoefficient);
					}
			for (const char* model : { vb::WillettCapillary::name, vb::RabinovichCapillary::name })
				for (double theta : { 0.0, 0.7 })
					for (double volumeRel : { 0.001, 0.01, 0.1 }) {
						vb::BridgeInputs b;
						b.rBar = rBar, b.radius1 = r1, b.radius2 = r2, b.surfaceTension = 0.072, b.contactAngle = theta;
						b.volume = volumeRel * 4.0 / 3.0 * vb::pi * r1 * r1 * r1;
						b.sRup   = vb::ruptureDistance(b.volume, theta);
						vb::ModelSelection s;
						s.capillary               = vb::modelIndex<vb::CapillarySlot>("golden", model);
						const vb::PairConstants k = vb::makePairConstants(s, {}, b, 0);
						const std::string       common = kv("r1", r1) + ", " + kv("r2", r2) + ", " + kv("gamma", 0.072) + ", " + kv("theta", theta) + ", "
						        + kv("V", b.volume) + ", " + ks("model", model);
						golden("capillaryMaxStiffness", common + ", " + kv("sRup", b.sRup), k.capillaryStiffness);
						for (double f : { -0.01, 0.0, 1e-3, 0.1, 0.5, 1.0 }) {
							const double S = f * b.sRup;
							vb::visitModel(s.capillary, vb::CapillaryModels(), [&](auto i) {
								using M       = vb::CapillaryModels::At<decltype(i)::value>;
								const M& m    = k.capillary.as<M>();
								golden("capillaryForce", common + ", " + kv("S", S), m.force(S));
								golden("capillaryStiffness", common + ", " + kv("S", S), m.stiffness(S));
							});
						}
					}
		}
	for (double e : { 0.05, 0.3, 0.5, 0.9, 0.99, 1.0 })
		golden("dampingRatio", kv("e", e), vb::dampingRatioFromRestitution(e));
	for (double E : { 1e6, 1e9 })
		for (double nu : { 0.0, 0.3, 0.45 }) {
			golden("rayleighTime", kv("r", 5e-4) + ", " + kv("rho", 2500) + ", " + kv("E", E) + ", " + kv("nu", nu), vb::rayleighTime(5e-4, 2500, E, nu));
			for (double r2 : { 5e-4, 2e-3 }) {
				const vb::HertzMindlinConstants h = vb::hertzMindlinConstants({ E, nu, 0.5 }, { 2 * E, 0.2, 0.3 }, 5e-4, r2);
				const std::string in = kv("E1", E) + ", " + kv("nu1", nu) + ", " + kv("E2", 2 * E) + ", " + kv("nu2", 0.2) + ", " + kv("R1", 5e-4) + ", " + kv("R2", r2);
				golden("kno", in, h.kno);
				golden("kso", in, h.kso);
			}
		}
	for (double d : { 0.0, 1e3, 1e7 })
		for (double kappa : { 0.0, 1e6, 1e12 })
			golden("networkLimit", kv("d", d) + ", " + kv("kappa", kappa), vb::networkLimit(d, kappa));
	for (double V : { 1e-13, 5.2e-12 })
		for (double theta : { 0.0, 1.0 })
			golden("ruptureDistance", kv("V", V) + ", " + kv("theta", theta), vb::ruptureDistance(V, theta));
}

} // namespace

int main(int argc, char** argv)
{
	if (argc == 2 && !std::strcmp(argv[1], "--python")) printPython();
	else if (argc == 2 && !std::strcmp(argv[1], "--golden")) printGolden();
	else {
		std::fprintf(stderr, "usage: %s --python | --golden\n", argv[0]);
		return 2;
	}
	return 0;
}
