// calibration.json written and read; docs/calibration.md is the key reference.
#include "trainer/calibrate/calibration_file.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>

#include "hostio/atomic_file.hpp"
#include "trainer/model/motor_file.hpp"
#include "trainer/model/motor_json.hpp"
#include "trainer/data/sensor_fault.hpp"

namespace lptn::calibrate {
namespace {

using nlohmann::ordered_json;

// ---- writing ---------------------------------------------------------------------------------
// The document is built in ordered_json so that the file reads top-down in the documented order
// (format_version first, parameters in model order); to_json() hands out the same content.

// A float as the double nearest to its shortest decimal form: the file then says 0.1, not
// 0.10000000149011612, and reading it back gives the same float. Where double rounding would spoil
// that (a decimal within half a double ulp of a float midpoint) the exact value is kept instead.
double short_float(float f) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, f);
  double d = 0;
  std::from_chars(buf, r.ptr, d);
  return static_cast<float>(d) == f ? d : static_cast<double>(f);
}

ordered_json float_array(const std::vector<float>& v) {
  ordered_json a = ordered_json::array();
  for (float f : v) a.push_back(short_float(f));
  return a;
}

// JSON has no NaN: nlohmann would write null anyway; say so explicitly.
ordered_json number_or_null(double v) { return std::isnan(v) ? ordered_json(nullptr) : ordered_json(v); }

void put_metrics(ordered_json& o, const ErrorMetrics& stator, const ErrorMetrics& rotor) {
  o["rmse_stator_k"] = stator.rmse_k;
  o["mean_abs_stator_k"] = stator.mean_abs_k;
  o["max_abs_stator_k"] = stator.max_abs_k;
  o["bias_stator_k"] = stator.bias_k;
  o["samples_stator"] = stator.samples;
  if (rotor.samples == 0) return;  // the rotor is not measured: no rotor keys at all
  o["rmse_rotor_k"] = rotor.rmse_k;
  o["mean_abs_rotor_k"] = rotor.mean_abs_k;
  o["max_abs_rotor_k"] = rotor.max_abs_k;
  o["bias_rotor_k"] = rotor.bias_k;
  o["samples_rotor"] = rotor.samples;
}

}  // namespace

nlohmann::ordered_json split_metrics_json(const SplitMetrics& m) {
  ordered_json o = ordered_json::object();
  put_metrics(o, m.stator, m.rotor);
  o["cycles"] = ordered_json::array();
  for (const CycleMetrics& c : m.cycles) {
    ordered_json cj = {{"name", c.name}};
    put_metrics(cj, c.stator, c.rotor);
    o["cycles"].push_back(cj);
  }
  return o;
}

namespace {

ordered_json actor_json(const ActorExport& a) {
  ordered_json o;
  o["obs_offset"] = a.obs_offset;
  o["obs_scale"] = a.obs_scale;
  o["layers"] = ordered_json::array();
  for (const ActorLayer& l : a.layers)
    o["layers"].push_back({{"in", l.in}, {"out", l.out}, {"weight", float_array(l.weight)}, {"bias", float_array(l.bias)}});
  o["param_indices"] = a.param_indices;
  o["param_names"] = ordered_json::array();
  for (int i : a.param_indices)
    o["param_names"].push_back(i >= 0 && i < kNumParams ? std::string(param_spec(i).name) : std::string("?"));
  o["check_obs"] = float_array(a.check_obs);
  o["check_actions"] = float_array(a.check_actions);
  return o;
}

ordered_json build(const CalibrationResult& r) {
  ordered_json j;
  j["format_version"] = r.format_version;
  j["created_utc"] = r.created_utc;
  j["lptn_version"] = r.lptn_version;
  j["status"] = r.status;
  j["warnings"] = ordered_json::array();
  for (const CalibrationWarning& w : r.warnings)
    j["warnings"].push_back({{"code", w.code}, {"message", w.message}, {"parameters", w.parameters}});
  j["motor"] = motor_json(r.motor);
  j["motor"]["file"] = r.motor.path.string();
  j["motor"]["text"] = r.motor.text;
  j["effects"] = ordered_json::array();
  for (int e = 0; e < kNumEffects; ++e)
    if (r.effects & effect_bit(e)) j["effects"].push_back(std::string(EffectLibrary::kNames[e]));

  j["parameters"] = ordered_json::array();
  for (const ParameterResult& p : r.parameters)
    j["parameters"].push_back({{"name", p.name},
                               {"unit", p.unit},
                               {"value", p.value},
                               {"initial", p.initial},
                               {"min", p.min},
                               {"max", p.max},
                               {"calibrated", p.calibrated},
                               {"std_error", number_or_null(p.std_error)},
                               {"identifiable", p.identifiable},
                               {"identifiability", p.identifiability}});
  j["correlated"] = ordered_json::array();
  for (const CorrelatedPair& c : r.correlated) j["correlated"].push_back({{"a", c.a}, {"b", c.b}, {"correlation", c.correlation}});

  j["method"] = {{"name", r.method}, {"settings", ordered_json(r.settings)}, {"details", ordered_json(r.details)}, {"seconds", r.seconds}};

  ordered_json files = ordered_json::array();
  for (const DataFile& f : r.data) {
    ordered_json file = {{"cycle", f.cycle}, {"file", f.file}, {"sha256", f.sha256}};
    // The data map it was read through: null for lptn's own CSV.
    if (f.map_recorded)
      file["map"] = f.map_sha256.empty() ? ordered_json(nullptr) : ordered_json{{"file", f.map_file}, {"sha256", f.map_sha256}};
    files.push_back(std::move(file));
  }
  j["data"] = {{"sha256", r.data_sha256},
               {"files", files},
               {"split", {{"rule", r.split_rule}, {"train", r.train_cycles}, {"test", r.test_cycles}}}};
  if (!r.sensor_faults.empty()) j["data"]["sensor_faults"] = r.sensor_faults;
  j["metrics"] = {{"train", split_metrics_json(r.train)}, {"test", split_metrics_json(r.test)}};
  if (r.has_actor) j["actor"] = actor_json(r.actor);
  return j;
}

// ---- reading ---------------------------------------------------------------------------------

std::vector<std::string> strings(const hostio::JsonField& f) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < f.size(); ++i) out.push_back(f.at(i).string());
  return out;
}

std::vector<float> floats(const hostio::JsonField& f) {
  std::vector<float> out;
  for (std::size_t i = 0; i < f.size(); ++i) out.push_back(static_cast<float>(f.at(i).number()));
  return out;
}

int parameter_named(const hostio::JsonField& f) {
  const std::string name = f.string();
  const int index = param_index(name);
  if (index < 0) f.fail("unknown parameter '" + name + "'");
  return index;
}

void read_metrics(const hostio::JsonField& f, ErrorMetrics& stator, ErrorMetrics& rotor) {
  stator.rmse_k = f["rmse_stator_k"].number();
  stator.mean_abs_k = f["mean_abs_stator_k"].number();
  stator.max_abs_k = f["max_abs_stator_k"].number();
  stator.bias_k = f["bias_stator_k"].number();
  stator.samples = f["samples_stator"].count();
  rotor = ErrorMetrics{};
  if (!f.has("rmse_rotor_k") && !f.has("samples_rotor")) return;  // rotor not measured
  rotor.rmse_k = f["rmse_rotor_k"].number();
  rotor.mean_abs_k = f["mean_abs_rotor_k"].number();
  rotor.max_abs_k = f["max_abs_rotor_k"].number();
  rotor.bias_k = f["bias_rotor_k"].number();
  rotor.samples = f["samples_rotor"].count();
}

SplitMetrics read_split(const hostio::JsonField& f) {
  SplitMetrics m;
  read_metrics(f, m.stator, m.rotor);
  const hostio::JsonField cycles = f["cycles"];
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    CycleMetrics c;
    c.name = cycles.at(i)["name"].string();
    read_metrics(cycles.at(i), c.stator, c.rotor);
    m.cycles.push_back(std::move(c));
  }
  return m;
}

// Every parameter of the model must be listed, except those of effects the calibration does not
// enable: a file written before an effect was appended to the library (docs/effects.md) lacks
// them, and they take no part in its model.
std::vector<ParameterResult> read_parameters(const hostio::JsonField& list, EffectSet effects, int version) {
  std::vector<ParameterResult> out(kNumParams);
  std::vector<bool> seen(kNumParams, false);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const hostio::JsonField p = list.at(i);
    const int index = parameter_named(p["name"]);
    if (seen[index]) p["name"].fail("'" + std::string(param_spec(index).name) + "' appears twice");
    seen[index] = true;
    ParameterResult& r = out[index];
    r.name = param_spec(index).name;
    r.unit = p["unit"].string();
    if (r.unit != param_spec(index).unit)
      p["unit"].fail("'" + r.unit + "', but this lptn has " + r.name + " in '" + std::string(param_spec(index).unit) + "'");
    r.value = p["value"].number();
    r.initial = p["initial"].number();
    r.min = p["min"].number();
    r.max = p["max"].number();
    r.calibrated = p["calibrated"].boolean();
    r.std_error = p["std_error"].number_or_null();
    if (version >= 2) {
      r.identifiable = p["identifiable"].boolean();
      r.identifiability = p["identifiability"].string();
    }
  }
  for (int i = 0; i < kNumParams; ++i) {
    if (seen[i]) continue;
    const int effect = effect_of_param(i);
    if (effect >= 0 && !(effects & effect_bit(effect))) {
      const ParamSpec& spec = param_spec(i);
      ParameterResult& r = out[i];
      r.name = spec.name;
      r.unit = spec.unit;
      r.value = r.initial = spec.initial;
      r.min = spec.min;
      r.max = spec.max;
      r.calibrated = false;
      r.std_error = std::nan("");
      continue;
    }
    list.fail("'" + std::string(param_spec(i).name) + "' is missing (every parameter of the model is listed; " +
                "a file from an lptn with a different parameter set?)");
  }
  return out;
}

ActorExport read_actor(const hostio::JsonField& f) {
  ActorExport a;
  const hostio::JsonField offset = f["obs_offset"], scale = f["obs_scale"];
  if (offset.size() != 2) offset.fail("expected 2 numbers (speed_rpm, torque_nm)");
  if (scale.size() != 2) scale.fail("expected 2 numbers (speed_rpm, torque_nm)");
  for (std::size_t i = 0; i < 2; ++i) {
    a.obs_offset[i] = offset.at(i).number();
    a.obs_scale[i] = scale.at(i).number();
    if (!(a.obs_scale[i] != 0)) scale.at(i).fail("must not be zero");
  }
  const hostio::JsonField layers = f["layers"];
  if (layers.size() == 0) layers.fail("expected at least one layer");
  for (std::size_t i = 0; i < layers.size(); ++i) {
    const hostio::JsonField l = layers.at(i);
    ActorLayer layer;
    layer.in = static_cast<int>(l["in"].integer());
    layer.out = static_cast<int>(l["out"].integer());
    if (layer.in <= 0) l["in"].fail("must be positive");
    if (layer.out <= 0) l["out"].fail("must be positive");
    const int expected_in = i == 0 ? 2 : a.layers.back().out;
    if (layer.in != expected_in)
      l["in"].fail(std::to_string(layer.in) + ", but the " + (i == 0 ? "observation has" : "layer before gives") + " " +
                   std::to_string(expected_in));
    layer.weight = floats(l["weight"]);
    layer.bias = floats(l["bias"]);
    if (layer.weight.size() != static_cast<std::size_t>(layer.in) * layer.out)
      l["weight"].fail(std::to_string(layer.weight.size()) + " numbers, expected in x out = " + std::to_string(layer.in * layer.out));
    if (layer.bias.size() != static_cast<std::size_t>(layer.out))
      l["bias"].fail(std::to_string(layer.bias.size()) + " numbers, expected out = " + std::to_string(layer.out));
    a.layers.push_back(std::move(layer));
  }
  const hostio::JsonField indices = f["param_indices"], names = f["param_names"];
  const std::size_t outputs = static_cast<std::size_t>(a.layers.back().out);
  if (indices.size() != outputs)
    indices.fail(std::to_string(indices.size()) + " entries, but the last layer has " + std::to_string(outputs) + " outputs");
  if (names.size() != outputs) names.fail(std::to_string(names.size()) + " entries, expected " + std::to_string(outputs));
  // The names are what a reader trusts; the indices must agree with them.
  for (std::size_t i = 0; i < outputs; ++i) {
    const int by_name = parameter_named(names.at(i));
    if (indices.at(i).integer() != by_name)
      indices.at(i).fail(std::to_string(indices.at(i).integer()) + ", but param_names[" + std::to_string(i) + "] '" +
                         names.at(i).string() + "' is parameter " + std::to_string(by_name));
    a.param_indices.push_back(by_name);
  }
  a.check_obs = floats(f["check_obs"]);
  a.check_actions = floats(f["check_actions"]);
  if (a.check_obs.size() % 2 != 0) f["check_obs"].fail("expected pairs (speed, torque), got an odd count");
  if (a.check_actions.size() != a.check_obs.size() / 2 * outputs)
    f["check_actions"].fail(std::to_string(a.check_actions.size()) + " numbers, expected " +
                            std::to_string(a.check_obs.size() / 2) + " checks x " + std::to_string(outputs) + " outputs");
  return a;
}

}  // namespace

ParamVector<double> CalibrationResult::values() const {
  ParamVector<double> v = default_params<double>();
  for (std::size_t i = 0; i < parameters.size() && i < v.size(); ++i) v[i] = parameters[i].value;
  return v;
}

nlohmann::json to_json(const CalibrationResult& result) { return nlohmann::json(build(result)); }

CalibrationResult calibration_from_json(const nlohmann::json& j, const std::string& shown_as) {
  if (!j.is_object()) throw CalibrationFileError(shown_as + ": not a calibration file (expected a JSON object)");
  if (!j.contains("format_version"))
    throw CalibrationFileError(shown_as + ": not a calibration file (no format_version" +
                               (j.contains("cycles") && j.contains("plant_physics") ? "; this is a generated dump's truth.json)"
                                : j.contains("candidates") ? "; this is a diagnosis, lptn diagnose --json-out's)"
                                                            : ")"));
  if (j.contains("pooled") && j.contains("fleet") && j.contains("motors"))
    throw CalibrationFileError(shown_as + ": a fleet calibration (fleet.json), not one motor's: give it as --fleet "
                                          "(lptn export --fleet F --motor-id ID, lptn report --fleet F, lptn check --fleet)");
  const hostio::JsonField root(j, "", shown_as);
  CalibrationResult r;
  // The version first: a file of another version may differ in any other key.
  const hostio::JsonField version = root["format_version"];
  r.format_version = static_cast<int>(version.integer());
  if (r.format_version < kOldestReadCalibrationFormatVersion || r.format_version > kCalibrationFormatVersion)
    version.fail("version " + std::to_string(r.format_version) + ", this lptn reads " +
                 std::to_string(kOldestReadCalibrationFormatVersion) + " to " + std::to_string(kCalibrationFormatVersion));
  if (r.format_version >= 2) {
    r.status = root["status"].string();
    if (r.status != kStatusOk && r.status != kStatusWarnings && r.status != kStatusFailed)
      root["status"].fail("'" + r.status + "', expected ok, warnings or failed");
    const hostio::JsonField warnings = root["warnings"];
    for (std::size_t i = 0; i < warnings.size(); ++i) {
      const hostio::JsonField w = warnings.at(i);
      r.warnings.push_back({w["code"].string(), w["message"].string(), strings(w["parameters"])});
    }
  } else {
    r.status = kStatusUnchecked;
    r.warnings.push_back({"unchecked", "made by an lptn that did not judge its outcome (format 1): a parameter marked "
                                       "calibrated may be the motor file's guess; calibrate again to know",
                          {}});
  }
  r.created_utc = root["created_utc"].string();
  r.lptn_version = root["lptn_version"].string();

  const hostio::JsonField motor = root["motor"];
  if (r.format_version >= 3) {
    r.motor = motor_from_json(motor);
  } else {
    // Before format 3 the motor was its TOML text alone.
    try {
      r.motor = parse_motor_file(motor["text"].string(), "motor.text");
    } catch (const MotorFileError& e) {
      // "motor.text:LINE: key 'K': reason" -> "FILE: field 'motor.text': line LINE: key 'K': reason".
      motor["text"].fail("line " + std::string(e.what()).substr(std::string("motor.text:").size()));
    }
  }
  r.motor.path = motor["file"].string();
  r.motor.text = motor["text"].string();

  const hostio::JsonField effects = root["effects"];
  for (std::size_t i = 0; i < effects.size(); ++i) {
    const std::string name = effects.at(i).string();
    const int e = effect_index(name);
    if (e < 0) effects.at(i).fail("unknown effect '" + name + "'");
    r.effects |= effect_bit(e);
  }

  r.parameters = read_parameters(root["parameters"], r.effects, r.format_version);
  const hostio::JsonField correlated = root["correlated"];
  for (std::size_t i = 0; i < correlated.size(); ++i) {
    const hostio::JsonField c = correlated.at(i);
    CorrelatedPair pair;
    pair.a = param_spec(parameter_named(c["a"])).name;
    pair.b = param_spec(parameter_named(c["b"])).name;
    pair.correlation = c["correlation"].number();
    r.correlated.push_back(std::move(pair));
  }

  const hostio::JsonField method = root["method"];
  r.method = method["name"].string();
  if (r.method.empty()) method["name"].fail("must not be empty");
  r.settings = method["settings"].json();
  r.details = method["details"].json();
  r.seconds = method["seconds"].number();

  const hostio::JsonField data = root["data"];
  r.data_sha256 = data["sha256"].string();
  const hostio::JsonField files = data["files"];
  for (std::size_t i = 0; i < files.size(); ++i) {
    const hostio::JsonField f = files.at(i);
    DataFile d;
    d.cycle = f["cycle"].string();
    d.file = f["file"].string();
    d.sha256 = f["sha256"].string();
    d.map_recorded = f.has("map");
    if (d.map_recorded && !f["map"].json().is_null()) {
      d.map_file = f["map"]["file"].string();
      d.map_sha256 = f["map"]["sha256"].string();
      if (d.map_sha256.empty()) f["map"]["sha256"].fail("must not be empty (null for no data map)");
    }
    r.data.push_back(std::move(d));
  }
  const hostio::JsonField split = data["split"];
  r.split_rule = split["rule"].string();
  r.train_cycles = strings(split["train"]);
  r.test_cycles = strings(split["test"]);
  if (data.has("sensor_faults")) {
    r.sensor_faults = strings(data["sensor_faults"]);
    // Checked here, once, so that whoever corrects readings with them has only the data to ask.
    for (std::size_t i = 0; i < r.sensor_faults.size(); ++i) try {
        data::parse_sensor_fault(r.sensor_faults[i]);
      } catch (const hostio::BadInput& e) {
        data["sensor_faults"].at(i).fail(e.what());
      }
  }

  const hostio::JsonField metrics = root["metrics"];
  r.train = read_split(metrics["train"]);
  r.test = read_split(metrics["test"]);

  r.has_actor = root.has("actor");
  if (r.has_actor) r.actor = read_actor(root["actor"]);
  return r;
}

void save_calibration(const CalibrationResult& result, const std::filesystem::path& path) {
  hostio::write_file_atomically(path, build(result).dump(2) + "\n");
}

nlohmann::json read_lptn_json(const std::filesystem::path& path) {
  const std::string shown = path.string();
  const std::string text = hostio::read_text_file(path);
  // A file of another kind (a motor file, a cycle CSV) is named as such, not as a JSON syntax error.
  const InputKind kind = input_kind(text);
  const std::size_t first = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  const bool looks_toml = first != std::string::npos && (std::isalpha(static_cast<unsigned char>(text[first])) ||
                                                         text[first] == '#') && text.find('=') != std::string::npos;
  if ((kind == InputKind::motor_toml && looks_toml) || kind == InputKind::cycle_csv)
    throw CalibrationFileError(shown + ": " + std::string(input_kind_words(kind)) + ", not a calibration (JSON)" +
                               (kind == InputKind::motor_toml ? ": give it as --motor" : ": give it as --data"));
  return hostio::parse_json_text(text, shown);
}

CalibrationResult load_calibration(const std::filesystem::path& path) {
  return calibration_from_json(read_lptn_json(path), path.string());
}

}  // namespace lptn::calibrate
