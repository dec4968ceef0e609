// Integrator option keys and the title's integrator label (see integrator_controls.h).
#include "preview/integrator_controls.h"

#include "scene/integrator_options.h"

namespace penumbra::preview {
namespace {

bool setStrategy(IntegratorSettings& settings, Strategy strategy) {
    if (settings.strategy == strategy) return false;
    settings.strategy = strategy;
    return true;
}

}  // namespace

bool isIntegratorAction(Action action) {
    switch (action) {
        case Action::StrategyLight:
        case Action::StrategyBsdf:
        case Action::StrategyMis:
        case Action::StrategyMixture:
        case Action::StrategyRis:
        case Action::ToggleHeuristic:
        case Action::CycleSphereSampling:
        case Action::ToggleQuadSampling:
        case Action::ToggleTriangleSampling:
        case Action::CycleLightSelection: return true;
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
        case Action::StrategyRis: return setStrategy(settings, Strategy::Ris);
        case Action::ToggleHeuristic: settings.heuristic = nextValue(settings.heuristic); return true;
        case Action::CycleSphereSampling: settings.sphereSampling = nextValue(settings.sphereSampling); return true;
        case Action::ToggleQuadSampling:
            settings.quadSampling = nextValue(settings.quadSampling);
            settings.quadSamplingGiven = true;
            return true;
        case Action::ToggleTriangleSampling:
            settings.triangleSampling = nextValue(settings.triangleSampling);
            settings.triangleSamplingGiven = true;
            return true;
        case Action::CycleLightSelection: settings.lightSelection = nextValue(settings.lightSelection); return true;
        default: return false;
    }
}

std::string integratorLabel(const IntegratorSettings& settings) {
    if (settings.type == IntegratorType::AmbientOcclusion) return std::string("ao ") + toName(settings.aoSampling);
    std::string label = toName(settings.strategy);
    if (settings.strategy == Strategy::Mis) label += std::string(" ") + toName(settings.heuristic);
    label += std::string(", spheres ") + toName(settings.sphereSampling);
    // The default selection stays unnamed, as in the labels before the light-selection key.
    if (settings.lightSelection != LightSelection::Power)
        label += std::string(", lights ") + toName(settings.lightSelection);
    return label;
}

}  // namespace penumbra::preview
