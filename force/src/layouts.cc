// The registry of tribometer export layouts (wearscar/force/layouts.h):
// one entry per layout, the generic delimited export last.

#include "wearscar/force/layouts.h"

#include <algorithm>

namespace wearscar::force {
namespace {

using C = ForceChannel;
using M = WordMatch;

bool HasName(const LayoutFacts& f, std::string_view part) {
  return std::any_of(f.names.begin(), f.names.end(), [&](const auto& n) {
    return n.find(part) != std::string::npos;
  });
}

bool HasUnit(const LayoutFacts& f, std::string_view unit) {
  return std::find(f.units.begin(), f.units.end(), unit) != f.units.end();
}

ForceLayout Rtec() {
  return {"rtec",
          "Rtec MFT-5000 / MFT-2000 recipe export (DAQ.Fx, DAQ.Fz, Piezo X; "
          "the Timestamp restarts with each RecipeStep)",
          {".csv"},
          {{C::kX, 3, M::kPart, "piezo x", ""},
           {C::kStep, 1, M::kPart, "recipestep", ""},
           {C::kStep, 1, M::kEquals, "step", ""}},
          "s",
          "mm",
          "N",
          ClockRule::kRestartsWithStep,
          [](const LayoutFacts& f) {
            return HasName(f, "daq.") || HasName(f, "recipestep") ? 3 : 0;
          },
          "Recipe: wood-steel reciprocating,Operator: lab\n"
          "RecipeStep,Timestamp,DAQ.Fx (N),DAQ.Fz (N),DAQ.COF (),Piezo X "
          "(mm),\n"
          "1,0.0000,0.0000,-30.0000,0.0000,0.00000,\n"
          "1,0.0050,3.6117,-30.0975,0.1200,0.08952,\n"
          "1,0.0100,3.6221,-30.1843,0.1200,0.17895,\n"
          "2,0.0000,3.6301,-30.2510,0.1200,0.26821,\n"
          "2,0.0050,3.6349,-30.2906,0.1200,0.35720,\n"};
}

ForceLayout Bruker() {
  return {"bruker",
          "Bruker / CETR UMT Data Viewer export (a units row in g; every test "
          "step repeats its header block)",
          {".csv", ".txt"},
          {{C::kTangential, 2, M::kWord, "ff", ""}},
          "",
          "",
          "",
          ClockRule::kRestartsWithBlock,
          [](const LayoutFacts& f) {
            return f.units_row && (HasUnit(f, "gf") || HasUnit(f, "g")) ? 2 : 0;
          },
          "Created by CETR UMT Data Viewer ver. 1.138.266\n"
          "Step No. 1\n\n"
          "Fx,Fz,Z,Y,X,V1,V2,T,Ff,COF\n"
          "g,g,mm,mm,mm,mm/sec,mm/sec,sec,g,\n\n"
          "102.575,-3059.149,-1.2500,0.0000,0.00000,0.000,0.000,0.000,102.575,"
          "0.0335,\n"
          "368.296,-3069.086,-1.2500,0.0000,0.08952,1.000,0.000,0.005,368.296,"
          "0.1200,\n"
          "369.357,-3077.937,-1.2500,0.0000,0.17895,1.000,0.000,0.010,369.357,"
          "0.1200,\n"
          "370.173,-3084.740,-1.2500,0.0000,0.26821,1.000,0.000,0.015,370.173,"
          "0.1200,\n"};
}

ForceLayout AntonPaar() {
  return {"anton-paar",
          "Anton Paar TRB / TRB3 linear export (tab separated, decimal comma "
          "possible)",
          {".txt", ".csv"},
          {{C::kTangential, 3, M::kPart, "friction force", ""},
           {C::kNormal, 3, M::kPart, "normal force", ""},
           {C::kNormal, 3, M::kPart, "nominal load", ""},
           {C::kDepth, 3, M::kPart, "penetration depth", ""}},
          "s",
          "mm",
          "N",
          ClockRule::kIncreasing,
          [](const LayoutFacts& f) {
            return f.delimiter == '\t' && HasName(f, "friction force") ? 3 : 0;
          },
          "Anton Paar TRB3\tTribometer\n"
          "Sample\tbeech\n\n"
          "Time [s]\tLinear Position [mm]\tFriction Force [N]\tNormal force "
          "[mN]\n"
          "0,0000\t0,00000\t0,0000\t30000,00\n"
          "0,0050\t0,08952\t3,6117\t30097,46\n"
          "0,0100\t0,17895\t3,6221\t30184,27\n"
          "0,0150\t0,26821\t3,6301\t30251,02\n"
          "0,0200\t0,35720\t3,6349\t30290,63\n"
          "0,0250\t0,44584\t3,6359\t30299,11\n"
          "0,0300\t0,53404\t3,6331\t30275,97\n"
          "0,0350\t0,62171\t3,6269\t30224,15\n"};
}

ForceLayout HomeBuilt() {
  return {"home-built",
          "a home-built rig's log: no time column, the sampling rate in a "
          "line above the data ('Sampling frequency [Hz]: 200')",
          {".csv", ".txt", ".dat", ".tsv"},
          {},
          "",
          "",
          "",
          ClockRule::kIncreasing,
          [](const LayoutFacts& f) { return f.metadata_rate_hz > 0 ? 1 : 0; },
          "Sampling frequency [Hz]: 200; rig: pin-on-plate v2\n"
          "x [um];Ft [N];Fn [N]\n"
          "0.00;0.0000;30.0000\n"
          "89.52;3.6117;30.0975\n"
          "178.95;3.6221;30.1843\n"
          "268.21;3.6301;30.2510\n"};
}

// Any delimited export with named columns, in English, German or French.
ForceLayout Delimited() {
  return {"delimited",
          "any delimited text export (comma, semicolon or tab; a header row "
          "naming time, position, friction and normal force)",
          {".csv", ".txt", ".tsv", ".dat"},
          {{C::kTime, 3, M::kWord, "timestamp", ""},
           {C::kTime, 3, M::kEquals, "time", ""},
           {C::kTime, 3, M::kEquals, "t", ""},
           {C::kTime, 2, M::kWord, "time", ""},
           {C::kTime, 2, M::kWord, "zeit", ""},
           {C::kTime, 2, M::kWord, "temps", ""},
           {C::kX, 3, M::kWord, "position", ""},
           {C::kX, 3, M::kWord, "displacement", ""},
           {C::kX, 2, M::kEquals, "x", ""},
           {C::kX, 2, M::kWord, "pos", ""},
           {C::kX, 2, M::kWord, "stroke", ""},
           {C::kX, 2, M::kWord, "lvdt", ""},
           {C::kX, 2, M::kWord, "weg", ""},
           {C::kX, 2, M::kWord, "verschiebung", ""},
           {C::kX, 2, M::kWord, "deplacement", ""},
           {C::kX, 2, M::kPart, "d\xc3\xa9placement", ""},
           {C::kX, 1, M::kWord, "x", "fx"},
           {C::kTangential, 3, M::kWord, "fx", ""},
           {C::kTangential, 3, M::kPart, "tangential", ""},
           {C::kTangential, 2, M::kWord, "friction", ""},
           {C::kTangential, 2, M::kWord, "ft", ""},
           {C::kTangential, 2, M::kEquals, "q", ""},
           {C::kTangential, 2, M::kWord, "lateral", ""},
           {C::kTangential, 3, M::kWord, "reibkraft", ""},
           {C::kTangential, 3, M::kWord, "reibungskraft", ""},
           {C::kTangential, 3, M::kWord, "tangentialkraft", ""},
           {C::kTangential, 2, M::kWord, "frottement", ""},
           {C::kNormal, 3, M::kWord, "fz", ""},
           {C::kNormal, 3, M::kWord, "fn", ""},
           {C::kNormal, 2, M::kWord, "normal", ""},
           {C::kNormal, 2, M::kWord, "load", ""},
           {C::kNormal, 2, M::kEquals, "p", ""},
           {C::kNormal, 3, M::kWord, "normalkraft", ""},
           {C::kNormal, 3, M::kPart, "force normale", ""},
           {C::kNormal, 2, M::kWord, "auflast", ""},
           {C::kDepth, 3, M::kPart, "penetration", ""},
           {C::kDepth, 3, M::kWord, "depth", ""},
           {C::kDepth, 2, M::kEquals, "z", ""},
           {C::kDepth, 2, M::kPart, "z position", ""},
           {C::kDepth, 2, M::kPart, "fz position", ""},
           {C::kDepth, 2, M::kPart, "height", ""},
           {C::kNotAChannel, 0, M::kWord, "cof", ""},
           {C::kNotAChannel, 0, M::kWord, "mu", ""},
           {C::kNotAChannel, 0, M::kPart, "coefficient", ""}},
          "",
          "",
          "",
          ClockRule::kIncreasing,
          [](const LayoutFacts&) { return 1; },
          "time_s,x_mm,Q_N,P_N\n"
          "0.0000,0.00000,0.0000,30.0000\n"
          "0.0050,0.08952,3.6117,30.0975\n"
          "0.0100,0.17895,3.6221,30.1843\n"
          "0.0150,0.26821,3.6301,30.2510\n"};
}

}  // namespace

const std::vector<ForceLayout>& ForceLayouts() {
  static const std::vector<ForceLayout> layouts = {
      Rtec(), Bruker(), AntonPaar(), HomeBuilt(), Delimited()};
  return layouts;
}

const ForceLayout* FindForceLayout(std::string_view name) {
  for (const ForceLayout& l : ForceLayouts()) {
    if (l.name == name) return &l;
  }
  return nullptr;
}

const ForceLayout& DetectForceLayout(const LayoutFacts& facts) {
  const ForceLayout* best = &ForceLayouts().back();
  int best_score = 0;
  for (const ForceLayout& l : ForceLayouts()) {
    const int s = l.detect(facts);
    if (s > best_score) best = &l, best_score = s;
  }
  return *best;
}

std::vector<std::string> ForceExtensions() {
  std::vector<std::string> out;
  for (const ForceLayout& l : ForceLayouts()) {
    for (const std::string& e : l.extensions) {
      if (std::find(out.begin(), out.end(), e) == out.end()) out.push_back(e);
    }
  }
  return out;
}

}  // namespace wearscar::force
