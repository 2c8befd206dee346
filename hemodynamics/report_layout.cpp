#include "hemodynamics/report_layout.hpp"
#include "hemodynamics/ventricle.hpp"

#include <cmath>

#include <fmt/format.h>

namespace ibvalve::hemodynamics {

using Json = nlohmann::ordered_json;

namespace {

constexpr const char* baumgartner = "Baumgartner et al. 2017";
constexpr const char* zoghbi = "Zoghbi et al. 2017";

/// The value of metric `key`, if it has one.
std::optional<double> value_of(const Json& metrics, const std::string& key)
{
  const auto m = metrics.find(key);
  if (m == metrics.end() || !m->is_object()) return std::nullopt;
  const auto v = m->find("value");
  if (v == m->end() || !v->is_number() || !std::isfinite(v->get<double>())) return std::nullopt;
  return v->get<double>();
}

std::string text_of(const Json& metrics, const std::string& key, const char* field)
{
  const auto m = metrics.find(key);
  if (m == metrics.end() || !m->is_object()) return {};
  const auto f = m->find(field);
  return f != m->end() && f->is_string() ? f->get<std::string>() : std::string();
}

} // namespace

std::span<const HeadlineFigure> headline_figures()
{
  // The guidelines grade disease; a healthy valve lies on the near side of their mildest grade. Each
  // bound is the one the cited table gives for "mild" (or, for the velocity, for no obstruction).
  static const HeadlineFigure figures[] = {
      {"forward_volume", "forward volume", std::nullopt},
      {"regurgitant_fraction", "regurgitant fraction",
       ReferenceRange{30.0, std::nullopt, false, "< 30 (at most mild regurgitation)", zoghbi}},
      {"transvalvular_pressure_gradient", "mean transvalvular pressure gradient",
       ReferenceRange{20.0, std::nullopt, false, "< 20 (at most mild stenosis)", baumgartner}},
      {"effective_orifice_area", "effective orifice area",
       ReferenceRange{std::nullopt, 1.5, false, "> 1.5 (at most mild stenosis)", baumgartner}},
      {"energy_loss", "energy loss across the valve", std::nullopt},
      {"peak_forward_flow", "peak forward flow", std::nullopt},
      {"max_orifice_area", "largest orifice area", std::nullopt},
      // Aortic sclerosis, the grade below mild stenosis, is a peak velocity of at most 2.5 m/s: no
      // obstruction to flow.
      {"peak_velocity_open", "peak velocity (fully opened)",
       ReferenceRange{2.5, std::nullopt, true, "<= 2.5 (no obstruction)", baumgartner}},
  };
  return figures;
}

std::span<const ReferenceSource> reference_sources()
{
  static const ReferenceSource sources[] = {
      {baumgartner,
       "H. Baumgartner, J. Hung, J. Bermejo et al., Recommendations on the echocardiographic assessment of "
       "aortic valve stenosis: a focused update from the European Association of Cardiovascular Imaging "
       "and the American Society of Echocardiography. J Am Soc Echocardiogr 30:372-392 (2017); Eur Heart J "
       "Cardiovasc Imaging 18:254-275 (2017). Mild stenosis: peak velocity 2.6-2.9 m/s, mean gradient "
       "< 20 mmHg, valve area > 1.5 cm^2; aortic sclerosis: peak velocity <= 2.5 m/s"},
      {zoghbi,
       "W. A. Zoghbi, D. Adams, R. O. Bonow et al., Recommendations for noninvasive evaluation of native "
       "valvular regurgitation: a report from the American Society of Echocardiography developed in "
       "collaboration with the Society for Cardiovascular Magnetic Resonance. J Am Soc Echocardiogr "
       "30:303-371 (2017). Mild aortic regurgitation: regurgitant fraction < 30 %, regurgitant volume "
       "< 30 mL"},
  };
  return sources;
}

Json headline_document(const Json& metrics)
{
  Json rows = Json::array();
  for (const HeadlineFigure& f : headline_figures()) {
    const std::optional<double> v = value_of(metrics, f.key);
    std::string assessment;
    if (v && f.range) {
      const ReferenceRange& r = *f.range;
      const bool within =
          (!r.upper || *v < *r.upper || (r.upper_included && *v == *r.upper)) && (!r.lower || *v > *r.lower);
      assessment = within ? "within" : "outside";
    }
    rows.push_back(Json{{"key", f.key},
                        {"name", f.name},
                        {"symbol", text_of(metrics, f.key, "symbol")},
                        {"value", v ? Json(*v) : Json()},
                        {"unit", text_of(metrics, f.key, "unit")},
                        {"range", f.range ? f.range->text : ""},
                        {"source", f.range ? f.range->source : ""},
                        {"assessment", assessment}});
  }
  return rows;
}

Json plausibility_checks(const Json& metrics)
{
  Json checks = Json::array();
  const auto eoa = value_of(metrics, "effective_orifice_area"), goa = value_of(metrics, "max_orifice_area");
  if (eoa && goa && *eoa > *goa)
    checks.push_back(
        Json{{"check", "eoa_above_goa"},
             {"text", fmt::format("EOA {:.4g} cm^2 is larger than the largest geometric orifice GOA_max "
                                  "{:.4g} cm^2: an effective orifice (the jet's vena contracta) is never "
                                  "larger than the geometric one; suspect the TPG's probes or the density",
                                  *eoa, *goa)}});
  const auto start = value_of(metrics, "windkessel_pressure_start"),
             end = value_of(metrics, "windkessel_pressure_end");
  if (start && end && std::abs(*end - *start) > periodic_pressure_tolerance)
    checks.push_back(Json{
        {"check", "not_periodic"},
        {"text", fmt::format("not periodic: the Windkessel pressure ends the cycle at {:.4g} mmHg, {:.3g} "
                             "mmHg from the {:.4g} mmHg it started with (tolerance {:g} mmHg); the figures "
                             "are of a run still settling: run more cycles",
                             *end, *end - *start, *start, periodic_pressure_tolerance)}});
  return checks;
}

std::span<const char* const> metric_groups()
{
  static const char* const groups[] = {"flow and pressure", "valve motion", "leaflet mechanics",
                                       "ventricle and loop", "other"};
  return groups;
}

std::string metric_group(const std::string& key)
{
  auto starts = [&](const char* prefix) { return key.rfind(prefix, 0) == 0; };
  for (const char* k : {"max_orifice_area", "opening_duration", "fully_open_duration", "closing_duration"})
    if (key == k) return "valve motion";
  if (starts("leaflet_displacement_")) return "valve motion";
  if (starts("fiber_strain_") || starts("fiber_stress_") || key == "strain_variation" ||
      key == "stress_variation" || key == "fit_error")
    return "leaflet mechanics";
  for (const char* k :
       {"forward_volume", "regurgitant_volume", "leakage_volume", "regurgitant_fraction",
        "transvalvular_pressure_gradient", "rms_forward_flow", "effective_orifice_area", "energy_loss",
        "peak_forward_flow", "peak_regurgitant_flow", "ejection_duration", "net_volume",
        "mean_aortic_pressure", "systolic_aortic_pressure", "diastolic_aortic_pressure",
        "diastolic_leak_area", "windkessel_pressure_start", "windkessel_pressure_end", "outlet_volume"})
    if (key == k) return "flow and pressure";
  if (starts("peak_velocity_")) return "flow and pressure";
  if (is_ventricle_metric(key)) return "ventricle and loop";
  return "other";
}

} // namespace ibvalve::hemodynamics
