// The JSON every summary shares, so summary.json files name things the same way.
//
// Vocabulary used by every summary in moreau (C++ members, summary.json keys, Python attributes):
//   termination    moreau::Termination, written as its ToString name
//   ok             IsSuccess(termination); the member function ok() in C++
//   message        why it stopped (empty on success)
//   *_seconds      wall-clock seconds; total_seconds is the whole solve or run, the others
//                  are phases (setup_seconds, sweep_seconds, factorize_seconds, …)
//   settings       the options used, as written by the options' ToJson()
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "moreau/common/termination.h"

namespace moreau {

// {"termination": …, "ok": …, "message": …, "total_seconds": …}
nlohmann::json SummaryJson(Termination termination, std::string_view message,
                           double total_seconds);

// j as text (indent < 0: one line), every byte sequence that is not valid UTF-8 (a C3D label or a
// file name in another encoding) written as U+FFFD, the replacement character, so that writing
// never fails on the text's encoding.
std::string JsonText(const nlohmann::json& j, int indent = 2);

// v when finite, else null (JSON has no NaN or infinity).
nlohmann::json FiniteOrNull(double v);

}  // namespace moreau
