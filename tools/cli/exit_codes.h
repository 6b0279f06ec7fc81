// The exit status of every bitstep command (`bitstep help` lists them;
// replay/README.md, "Exit status"). Each failure also prints one line to
// stderr naming the file, the place and the reason.
#pragma once

namespace bitstep::exit_code {

inline constexpr int success = 0;
// A check failed: a hash differs (verify, synctest), two dumps differ
// (diff), a function is outside its bound (selftest), a peer timed out.
inline constexpr int check_failed = 1;
// A usage error: an unknown or malformed option or argument, --settings
// text that is not a settings object.
inline constexpr int usage = 2;
// bitstep peer: the peers' states differ (a desync, named by tick and field).
inline constexpr int desync = 3;
// An input file refused: missing or unreadable, over a limit
// (replay/limits.h), malformed, or not fitting what it is used with (a
// replay's scene, a snapshot of another scene, a scene body the world
// refuses).
inline constexpr int bad_input = 4;
// An output file could not be written (nothing is left under its name).
inline constexpr int output_failed = 5;
// bitstep peer: another peer refused our hello (another scene or settings,
// player count, mode, input delay, a player number taken or out of range,
// another build), named on both sides.
inline constexpr int refused = 6;

}  // namespace bitstep::exit_code
