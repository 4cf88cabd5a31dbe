// The verification sections of summary.json: probes, pins (support reactions), loads (applied totals),
// until_rest and the kinetic-energy history per frame (docs/cli.md).
#include <stdexcept>

#include "output/summary.hpp"

namespace shellfrac::output {

namespace {

using Json = nlohmann::json;

template <class T>
T read(const Json& j, const char* key) {
  if (!j.is_object() || !j.contains(key)) throw std::runtime_error(std::string("summary.json: missing field \"") + key + "\"");
  try {
    return j.at(key).get<T>();
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("summary.json: field \"") + key + "\": " + e.what());
  }
}

}  // namespace

void write_verification(const Summary& s, Json& j) {
  Json probes = Json::array();
  for (const ProbeReport& p : s.probes) {
    Json time = Json::array(), position = Json::array(), displacement = Json::array(), velocity = Json::array(),
         stress = Json::array();
    for (const ProbeRow& r : p.samples) {
      time.push_back(r.time);
      position.push_back(r.position);
      displacement.push_back(r.displacement);
      velocity.push_back(r.velocity);
      stress.push_back(r.stress);
    }
    probes.push_back({{"name", p.name}, {"shell", p.shell}, {"every", p.every}, {"file", p.file}, {"time", time},
                      {"position", position}, {"displacement", displacement}, {"velocity", velocity}, {"stress", stress}});
  }
  j["probes"] = std::move(probes);
  Json pins = Json::array();
  for (const PinReport& p : s.pins) pins.push_back({{"pin", p.pin}, {"name", p.name}, {"shell", p.shell}, {"reaction", p.reaction}});
  j["pins"] = std::move(pins);
  Json loads = Json::array();
  for (const LoadReport& l : s.loads) loads.push_back({{"load", l.load}, {"type", l.type}, {"shell", l.shell}, {"applied", l.applied}});
  j["loads"] = std::move(loads);
  if (s.until_rest) {
    const RestReport& r = *s.until_rest;
    j["until_rest"] = {{"reached", r.reached}, {"time", r.time ? Json(*r.time) : Json(nullptr)},
                       {"kinetic_energy", r.kinetic_energy}, {"speed", r.speed}, {"duration", r.duration}};
  }
  j["kinetic_energy_history"] = {{"time", s.kinetic_energy_history.time},
                                 {"kinetic_energy", s.kinetic_energy_history.kinetic_energy}};
}

void read_verification(const Json& j, Summary& s) {
  if (j.contains("probes"))
    for (const Json& p : j.at("probes")) {
      ProbeReport r{read<std::string>(p, "name"), read<std::string>(p, "shell"), read<std::string>(p, "every"),
                    read<std::string>(p, "file"), {}};
      const auto time = read<std::vector<double>>(p, "time");
      const auto position = read<std::vector<std::array<double, 3>>>(p, "position");
      const auto displacement = read<std::vector<std::array<double, 3>>>(p, "displacement");
      const auto velocity = read<std::vector<std::array<double, 3>>>(p, "velocity");
      const auto stress = read<std::vector<std::array<double, 6>>>(p, "stress");
      if (position.size() != time.size() || displacement.size() != time.size() || velocity.size() != time.size() ||
          stress.size() != time.size())
        throw std::runtime_error("summary.json: probe \"" + r.name + "\" has columns of different lengths");
      for (size_t k = 0; k < time.size(); ++k) r.samples.push_back({time[k], position[k], displacement[k], velocity[k], stress[k]});
      s.probes.push_back(std::move(r));
    }
  if (j.contains("pins"))
    for (const Json& p : j.at("pins"))
      s.pins.push_back({read<std::string>(p, "pin"), read<std::string>(p, "name"), read<std::string>(p, "shell"),
                        read<std::array<double, 3>>(p, "reaction")});
  if (j.contains("loads"))
    for (const Json& l : j.at("loads"))
      s.loads.push_back({read<std::string>(l, "load"), read<std::string>(l, "type"), read<std::string>(l, "shell"),
                         read<std::array<double, 3>>(l, "applied")});
  if (j.contains("until_rest")) {
    const Json& r = j.at("until_rest");
    RestReport out;
    out.reached = read<bool>(r, "reached");
    if (r.contains("time") && !r.at("time").is_null()) out.time = read<double>(r, "time");
    out.kinetic_energy = read<double>(r, "kinetic_energy");
    out.speed = read<double>(r, "speed");
    out.duration = read<double>(r, "duration");
    s.until_rest = out;
  }
  if (j.contains("kinetic_energy_history")) {
    const Json& h = j.at("kinetic_energy_history");
    s.kinetic_energy_history.time = read<std::vector<double>>(h, "time");
    s.kinetic_energy_history.kinetic_energy = read<std::vector<double>>(h, "kinetic_energy");
  }
}

}  // namespace shellfrac::output
