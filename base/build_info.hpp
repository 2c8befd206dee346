#pragma once
// What this ibvalve is and when it speaks: its version and the commit it was built from (`git
// describe`; "-modified" when the tree had uncommitted changes), and the time now, as every run folder
// (run.json) and report records them.
#include <string>

namespace ibvalve::base {

const char* version();
const char* commit();
/// The time now, UTC, ISO 8601 ("2026-12-02T09:41:07Z").
std::string utc_now();

} // namespace ibvalve::base
