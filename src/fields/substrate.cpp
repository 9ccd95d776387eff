// Substrate: its field list (every face at once, or face by face) and the periodic-face rule.
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/fields/field_set.h"

namespace moreau::fields {
namespace {

constexpr const char* kFaceNames[kFaces] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};

std::string KindList() {
  std::string out;
  for (const auto& [kind, name] : kBoundaryKindNames)
    out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

// of(face) when every face gives the same, else null.
template <typename F>
nlohmann::json Shared(const Substrate& s, F of) {
  const nlohmann::json first = of(s.boundary[0]);
  for (const FaceBoundary& f : s.boundary) {
    if (of(f) != first) return nlohmann::json();
  }
  return first;
}

// "boundary": every face's kind; reads as the kind when all faces share it, else null.
FieldList<Substrate>::Field EveryFaceKind() {
  return {"boundary",
          "one of " + KindList(),
          "",
          "",
          "every face's condition at once (then per face: x_min, …)",
          [](const Substrate& s) {
            return Shared(s, [](const FaceBoundary& f) {
              return nlohmann::json(std::string(EnumName(kBoundaryKindNames, f.kind)));
            });
          },
          [](Substrate& s, const nlohmann::json& j) -> std::string {
            if (!j.is_string()) return ExpectedType("a string", j);
            for (const auto& [kind, name] : kBoundaryKindNames) {
              if (name != j.get<std::string>()) continue;
              for (FaceBoundary& f : s.boundary) f.kind = kind;
              return "";
            }
            return fmt::format("must be one of {} (got \"{}\")", KindList(), j.get<std::string>());
          },
          nullptr};
}

// "boundary_value": every face's value; reads as the value when all faces share it, else null.
FieldList<Substrate>::Field EveryFaceValue() {
  return {"boundary_value",
          "number",
          "",
          "amount/volume",
          "c_b of every fixed face at once (then per face: x_min_value, …)",
          [](const Substrate& s) {
            return Shared(s, [](const FaceBoundary& f) { return nlohmann::json(f.value); });
          },
          [](Substrate& s, const nlohmann::json& j) -> std::string {
            if (!j.is_number()) return ExpectedType("a number", j);
            const double v = j.get<double>();
            std::string why = NumberViolation(Range::Any(), v);
            if (!why.empty()) return why;
            for (FaceBoundary& f : s.boundary) f.value = v;
            return "";
          },
          nullptr};
}

// The rule on face f: periodic exactly when its opposite face is.
std::string PeriodicPair(const Substrate& s, int f) {
  const int opposite = f ^ 1;
  const bool periodic = s.boundary[f].kind == BoundaryKind::kPeriodic;
  if (periodic || s.boundary[opposite].kind != BoundaryKind::kPeriodic) return "";
  return fmt::format("must be periodic as {} is (got {})", kFaceNames[opposite],
                     EnumName(kBoundaryKindNames, s.boundary[f].kind));
}

}  // namespace

const FieldList<Substrate>& Substrate::Fields() {
  using S = Substrate;
  static const FieldList<S> list = [] {
    FieldList<S> t;
    t.Text("name", &S::name, "unique among the substrates")
        .Number("diffusion", &S::diffusion, Range::Positive(), "length²/time",
                "D: diffusion coefficient")
        .Number("decay", &S::decay, Range::NonNegative(), "1/time", "λ: decay rate")
        .Number("initial", &S::initial, Range::Any(), "amount/volume", "c(x, 0)")
        .Custom(EveryFaceKind())
        .Custom(EveryFaceValue());
    for (int f = 0; f < kFaces; ++f) {
      t.Choice(
          kFaceNames[f],
          [f](auto& s) -> auto& { return s.boundary[static_cast<std::size_t>(f)].kind; },
          kBoundaryKindNames, fmt::format("the {} face's condition", kFaceNames[f]));
      t.Number(
          fmt::format("{}_value", kFaceNames[f]),
          [f](auto& s) -> auto& { return s.boundary[static_cast<std::size_t>(f)].value; },
          Range::Any(), "amount/volume",
          fmt::format("c_b on the {} face when fixed", kFaceNames[f]));
    }
    t.Rule("name", [](const S& s) { return s.name.empty() ? "must not be empty" : ""; });
    for (int f = 0; f < kFaces; ++f) {
      t.Rule(kFaceNames[f], [f](const S& s) { return PeriodicPair(s, f); });
    }
    return t;
  }();
  return list;
}

}  // namespace moreau::fields
