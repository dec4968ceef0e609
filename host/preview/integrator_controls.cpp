// Integrator option keys and the title's integrator label (see integrator_controls.h).
#include "preview/integrator_controls.h"

namespace penumbra::preview {
namespace {

// The names of SCENE_FORMAT.md, as the scene file spells them.
const char* strategyName(Strategy s) {
    switch (s) {
        case Strategy::Light: return "light";
        case Strategy::Bsdf: return "bsdf";
        case Strategy::Mis: return "mis";
        case Strategy::Mixture: return "mixture";
    }
    return "?";
}
const char* heuristicName(Heuristic h) { return h == Heuristic::Balance ? "balance" : "power"; }
const char* sphereName(SphereSampling s) {
    return s == SphereSampling::Area ? "area" : s == SphereSampling::Cap ? "cap" : "solid_angle";
}

bool setStrategy(IntegratorSettings& settings, Strategy strategy) {
    if (settings.strategy == strategy) return false;
    settings.strategy = strategy;
    settings.json["strategy"] = strategyName(strategy);
    return true;
}

}  // namespace

bool isIntegratorAction(Action action) {
    switch (action) {
        case Action::StrategyLight:
        case Action::StrategyBsdf:
        case Action::StrategyMis:
        case Action::StrategyMixture:
        case Action::ToggleHeuristic:
        case Action::CycleSphereSampling:
        case Action::ToggleQuadSampling:
        case Action::ToggleTriangleSampling: return true;
        default: return false;
    }
}

bool applyIntegratorAction(IntegratorSettings& settings, Action action) {
    if (settings.type != IntegratorType::Direct) return false;
    switch (action) {
        case Action::StrategyLight: return setStrategy(settings, Strategy::Light);
        case Action::StrategyBsdf: return setStrategy(settings, Strategy::Bsdf);
        case Action::StrategyMis: return setStrategy(settings, Strategy::Mis);
        case Action::StrategyMixture: return setStrategy(settings, Strategy::Mixture);
        case Action::ToggleHeuristic:
            settings.heuristic = settings.heuristic == Heuristic::Power ? Heuristic::Balance : Heuristic::Power;
            settings.json["heuristic"] = heuristicName(settings.heuristic);
            return true;
        case Action::CycleSphereSampling:
            settings.sphereSampling = settings.sphereSampling == SphereSampling::Area ? SphereSampling::Cap
                                      : settings.sphereSampling == SphereSampling::Cap ? SphereSampling::SolidAngle
                                                                                      : SphereSampling::Area;
            settings.json["sphere_sampling"] = sphereName(settings.sphereSampling);
            return true;
        case Action::ToggleQuadSampling:
            settings.quadSampling = settings.quadSampling == QuadSampling::Area ? QuadSampling::SolidAngle
                                                                                : QuadSampling::Area;
            settings.json["quad_sampling"] = settings.quadSampling == QuadSampling::Area ? "area" : "solid_angle";
            return true;
        case Action::ToggleTriangleSampling:
            settings.triangleSampling = settings.triangleSampling == TriangleSampling::Area
                                            ? TriangleSampling::SolidAngle
                                            : TriangleSampling::Area;
            settings.json["triangle_sampling"] = settings.triangleSampling == TriangleSampling::Area ? "area"
                                                                                                     : "solid_angle";
            return true;
        default: return false;
    }
}

std::string integratorLabel(const IntegratorSettings& settings) {
    if (settings.type == IntegratorType::AmbientOcclusion)
        return std::string("ao ") + (settings.aoSampling == AoSampling::Cosine ? "cosine" : "uniform");
    std::string label = strategyName(settings.strategy);
    if (settings.strategy == Strategy::Mis) label += std::string(" ") + heuristicName(settings.heuristic);
    return label + ", spheres " + sphereName(settings.sphereSampling);
}

}  // namespace penumbra::preview
