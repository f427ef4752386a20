// Reader of the prediction-model YAML file (docs/prediction.md) into the domain's PredictionModel.
#include "mtcal/io/model/prediction_model_file.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"
#include "../text/yaml_reader.hpp"

namespace mtcal {
namespace {

constexpr int kFormatVersion = 1;

// The machine file reader's YAML helpers: the same located messages. Here an empty section is
// an error, so entries() is called with null_is_empty = false.
using namespace detail::yaml;
YAML::Node get(const Entries& e, const std::string& key) { return e[key]; }

// form + parameters (by name) or coefficients (polynomial c0..c3).
Model parse_model(const Entries& e, const YAML::Node& n, const Ctx& ctx) {
  const YAML::Node fn = get(e, "form");
  if (!fn.IsDefined())
    ctx.fail(n,
             "missing key 'form' (polynomial, exp_approach, stretched_exp, logistic_ln, gompertz, saturation, power)");
  const std::string fs = text(fn, ctx.child("form"));
  const auto form = model_form_from_string(fs);
  if (!form)
    ctx.child("form").fail(
        fn, "unknown model form '" + fs +
                "' (expected polynomial, exp_approach, stretched_exp, logistic_ln, gompertz, saturation, power)");
  Model m;
  m.spec.form = *form;
  if (*form == ModelForm::Polynomial) {
    const YAML::Node cn = get(e, "coefficients");
    if (!cn.IsDefined()) ctx.fail(n, "a polynomial needs 'coefficients: [c0, c1, c2, c3]'");
    if (get(e, "parameters").IsDefined())
      ctx.child("parameters").fail(get(e, "parameters"), "a polynomial takes 'coefficients', not 'parameters'");
    auto c = numbers(cn, ctx.child("coefficients"));
    if (c.empty() || c.size() > 4)
      ctx.child("coefficients")
          .fail(cn, fmt::format("expected 1 to 4 coefficients [c0, c1, c2, c3], found {}", c.size()));
    m.spec.degree = std::max(1, static_cast<int>(c.size()) - 1);
    c.resize(static_cast<std::size_t>(m.spec.degree) + 1, 0.0);
    m.p = c;
    return m;
  }
  const YAML::Node pn = get(e, "parameters");
  if (get(e, "coefficients").IsDefined())
    ctx.child("coefficients").fail(get(e, "coefficients"), fs + " takes 'parameters' by name, not 'coefficients'");
  const auto names = parameter_names(m.spec);
  std::string list;
  for (const auto& k : names) list += (list.empty() ? "" : ", ") + k;
  if (!pn.IsDefined()) ctx.fail(n, fmt::format("missing key 'parameters' ({}: {})", fs, list));
  const Ctx pc = ctx.child("parameters");
  if (!pn.IsMap()) pc.fail(pn, "expected a map {" + list + "}, found " + describe(pn));
  for (auto it = pn.begin(); it != pn.end(); ++it) {
    const std::string k = it->first.Scalar();
    if (std::find(names.begin(), names.end(), k) == names.end())
      pc.child(k).fail(it->first, fmt::format("unknown parameter '{}' of {} (expected {})", k, fs, list));
  }
  for (const auto& k : names) {
    const YAML::Node v = pn[k];
    if (!v.IsDefined()) pc.fail(pn, fmt::format("missing parameter '{}' of {} (expected {})", k, fs, list));
    m.p.push_back(number(v, pc.child(k)));
  }
  return m;
}

ErrorComponent parse_component(const YAML::Node& n, const Ctx& ctx, const std::vector<ErrorComponent>& earlier) {
  const auto e = entries(n, ctx,
                         {"name", "axis", "variable", "form", "parameters", "coefficients", "stages", "speed_variable",
                          "of", "scale", "times", "ramp", "valid", "source", "description"},
                         false);
  ErrorComponent c;
  c.line = n.Mark().line + 1;
  const YAML::Node nn = get(e, "name");
  if (!nn.IsDefined()) ctx.fail(n, "missing key 'name'");
  c.name = text(nn, ctx.child("name"));
  if (c.name.empty() || c.name.find_first_of(" ,\t") != std::string::npos)
    ctx.child("name").fail(nn, "expected a name without spaces or commas, found '" + printable(c.name) + "'");
  for (const auto& o : earlier)
    if (o.name == c.name)
      ctx.child("name").fail(nn, fmt::format("component '{}' is defined twice (first on line {})", c.name, o.line));
  const Ctx cc = ctx.child(c.name);
  const YAML::Node an = get(e, "axis");
  if (!an.IsDefined())
    cc.fail(n, "missing key 'axis' (x, y, z, or none for a component that is listed but not summed)");
  const std::string a = text(an, cc.child("axis"));
  if (a == "x" || a == "y" || a == "z")
    c.axis = a[0];
  else if (a != "none")
    cc.child("axis").fail(an, "expected x, y, z or none, found '" + printable(a) + "'");
  if (auto s = get(e, "source"); s.IsDefined()) c.source = text(s, cc.child("source"));
  if (auto s = get(e, "scale"); s.IsDefined()) c.scale = number(s, cc.child("scale"));
  if (auto s = get(e, "times"); s.IsDefined()) c.times = text(s, cc.child("times"));
  if (auto s = get(e, "speed_variable"); s.IsDefined()) c.speed_variable = text(s, cc.child("speed_variable"));

  const bool has_model =
      get(e, "form").IsDefined() || get(e, "parameters").IsDefined() || get(e, "coefficients").IsDefined();
  const bool has_stages = get(e, "stages").IsDefined();
  const bool has_of = get(e, "of").IsDefined();
  if (has_model + has_stages + has_of != 1)
    cc.fail(n, "expected exactly one of a model (form with parameters or coefficients), 'stages', or 'of'");
  if (has_of) {
    c.of = text(get(e, "of"), cc.child("of"));
    if (std::none_of(earlier.begin(), earlier.end(), [&](const ErrorComponent& o) { return o.name == c.of; }))
      cc.child("of").fail(get(e, "of"), "'" + printable(c.of) + "' is not a component defined above this one");
  } else {
    const YAML::Node vn = get(e, "variable");
    if (!vn.IsDefined()) cc.fail(n, "missing key 'variable' (the driving variable: a points column such as t, F, dx)");
    c.variable = text(vn, cc.child("variable"));
  }
  std::vector<YAML::Node> model_nodes;  // where each model's parameters are, for the domain check
  std::vector<Ctx> model_ctx;
  if (has_model) {
    c.model = parse_model(e, n, cc);
    const YAML::Node pn = get(e, c.model->spec.form == ModelForm::Polynomial ? "coefficients" : "parameters");
    model_nodes.push_back(pn);
    model_ctx.push_back(cc.child(c.model->spec.form == ModelForm::Polynomial ? "coefficients" : "parameters"));
  }
  if (has_stages) {
    const YAML::Node sn = get(e, "stages");
    const Ctx sc = cc.child("stages");
    if (!sn.IsSequence() || sn.size() < 2)
      sc.fail(sn, "expected a list of at least 2 stages {speed, form, ...}, found " + describe(sn));
    for (std::size_t i = 0; i < sn.size(); ++i) {
      const Ctx ic = sc.child(std::to_string(i));
      const auto se = entries(sn[i], ic, {"speed", "form", "parameters", "coefficients", "source"}, false);
      SpeedStage st;
      const YAML::Node sp = get(se, "speed");
      if (!sp.IsDefined()) ic.fail(sn[i], "missing key 'speed' (rpm)");
      st.speed = number(sp, ic.child("speed"));
      if (st.speed <= 0)
        ic.child("speed").fail(sp, fmt::format("expected a spindle speed > 0 rpm, found {:g}", st.speed));
      if (!c.stages.empty() && st.speed <= c.stages.back().speed)
        ic.child("speed").fail(sp, fmt::format("expected stages in increasing speed, found {:g} after {:g}", st.speed,
                                               c.stages.back().speed));
      st.model = parse_model(se, sn[i], ic);
      if (auto s = get(se, "source"); s.IsDefined()) st.source = text(s, ic.child("source"));
      c.stages.push_back(st);
      const bool poly = st.model.spec.form == ModelForm::Polynomial;
      model_nodes.push_back(get(se, poly ? "coefficients" : "parameters"));
      model_ctx.push_back(ic.child(poly ? "coefficients" : "parameters"));
    }
  }
  if (auto rn = get(e, "ramp"); rn.IsDefined()) {
    const Ctx rc = cc.child("ramp");
    const auto re = entries(rn, rc, {"variable", "zero_at", "one_at"}, false);
    Ramp r;
    for (const char* k : {"variable", "zero_at", "one_at"})
      if (!get(re, k).IsDefined()) rc.fail(rn, std::string("missing key '") + k + "'");
    r.variable = text(get(re, "variable"), rc.child("variable"));
    r.zero_at = number(get(re, "zero_at"), rc.child("zero_at"));
    r.one_at = number(get(re, "one_at"), rc.child("one_at"));
    if (r.one_at == r.zero_at) rc.fail(rn, "expected one_at != zero_at");
    c.ramp = r;
  }
  if (auto vn = get(e, "valid"); vn.IsDefined()) {
    if (has_of) cc.child("valid").fail(vn, "'valid' belongs to the component named by 'of'");
    const auto v = numbers(vn, cc.child("valid"));
    if (v.size() != 2 || !(v[0] <= v[1])) cc.child("valid").fail(vn, "expected [low, high] with low <= high");
    c.valid = std::make_pair(v[0], v[1]);
  }
  // Parameters outside a form's domain over the range the component is evaluated on (its
  // validity range, else the form's whole domain) are refused here, not at the first point.
  std::vector<const Model*> models;
  if (c.model) models.push_back(&*c.model);
  for (const auto& st : c.stages) models.push_back(&st.model);
  for (std::size_t i = 0; i < models.size(); ++i) {
    const double x_low = c.valid ? c.valid->first : domain_lower_bound(models[i]->spec.form);
    const std::string why = parameter_domain_problem(*models[i], x_low);
    if (!why.empty()) model_ctx[i].fail(model_nodes[i], why);
  }
  return c;
}

}  // namespace

PredictionModel parse_prediction_model(const std::string& text_in, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text_in);
  } catch (const YAML::Exception& e) {
    throw InputError({source, e.mark.line + 1, ""}, "not valid YAML: " + e.msg);
  }
  const Ctx ctx{source, ""};
  if (!root.IsMap())
    ctx.fail(root, "expected a prediction model (a map with 'mtcal_prediction_model' and 'components'), found " +
                       describe(root));
  const auto e = entries(root, ctx, {"mtcal_prediction_model", "name", "description", "units", "components"}, false);
  const YAML::Node vn = get(e, "mtcal_prediction_model");
  if (!vn.IsDefined()) ctx.fail(root, "missing key 'mtcal_prediction_model' (the format version, 1)");
  if (number(vn, ctx.child("mtcal_prediction_model")) != kFormatVersion)
    ctx.child("mtcal_prediction_model")
        .fail(vn, fmt::format("expected format version {}, found {}", kFormatVersion, vn.Scalar()));
  PredictionModel m;
  m.file = source;
  if (auto n = get(e, "name"); n.IsDefined()) m.name = text(n, ctx.child("name"));
  if (auto u = get(e, "units"); u.IsDefined()) {
    // The units are fixed (mm, min, mm/min, rpm); the key only documents them, so a file that
    // says otherwise is refused rather than misread.
    const auto ue = entries(u, ctx.child("units"), {"error", "distance", "time", "feed", "speed"}, false);
    const std::pair<const char*, const char*> fixed[] = {
        {"error", "mm"}, {"distance", "mm"}, {"time", "min"}, {"feed", "mm/min"}, {"speed", "rpm"}};
    for (const auto& [k, want] : fixed)
      if (auto n = get(ue, k); n.IsDefined() && text(n, ctx.child("units").child(k)) != want)
        ctx.child("units").child(k).fail(n, fmt::format("expected '{}' (the only unit mtcal reads here), found '{}'",
                                                        want, n.Scalar()));
  }
  const YAML::Node cn = get(e, "components");
  if (!cn.IsDefined()) ctx.fail(root, "missing key 'components'");
  if (!cn.IsSequence() || cn.size() == 0)
    ctx.child("components").fail(cn, "expected a non-empty list of components, found " + describe(cn));
  for (std::size_t i = 0; i < cn.size(); ++i)
    m.components.push_back(parse_component(cn[i], ctx.child("components"), m.components));
  return m;
}

PredictionModel read_prediction_model(const std::string& path) {
  return parse_prediction_model(read_text_file(path, "prediction model file", input_limits().yaml), path);
}

}  // namespace mtcal
