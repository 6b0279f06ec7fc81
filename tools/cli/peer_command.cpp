#include "tools/cli/peer_command.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <optional>
#include <map>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "replay/replay.h"
#include "replay/session_codec.h"
#include "replay/session_roster.h"
#include "tools/cli/enet_transport.h"
#include "tools/cli/options.h"
#include "tools/cli/exit_codes.h"

namespace bitstep {

namespace {

struct Options {
  std::string scene_path;
  std::vector<std::string> inputs;  // the local player's script (--reference: every player's, in order)
  std::vector<std::string> connect;
  int player = 0, players = 2;
  int port = 0;
  SessionConfig session;
  int64_t ticks = 600;
  double hz = 60;
  double timeout_s = 60;
  NetFaults faults;
  bool json = false, reference = false;
  std::vector<RosterEvent> roster;  // --reference: --absent, --present and --watching, in order
  int64_t chain_from = 0;           // --reference: the chain of the ticks after this one
  std::string corrupt_body;  // a test's cheat: flip a bit of this body's velocity ...
  int64_t corrupt_tick = 0;  // ... before this tick
};

// What the options say together: an empty string, or the one-line error.
std::string check_options(Options& o) {
  if (o.player >= o.players) return "--player must be below --players";
  if (o.reference && o.inputs.size() > static_cast<size_t>(o.players)) return "--reference takes at most one --inputs per player";
  if (!o.reference && o.inputs.size() > 1) return "--inputs: one script, the local player's";
  if (!o.reference && o.players > 1 && o.port == 0) return "--port is required with more than one player";
  if (!o.reference && (!o.roster.empty() || o.chain_from > 0)) {
    return "--absent, --present, --watching and --chain-from go with --reference";
  }
  if (o.session.watching && !o.inputs.empty()) return "--watch: a spectator gives no --inputs";
  if (o.chain_from >= o.ticks) return "--chain-from must be below --ticks";
  for (const RosterEvent& e : o.roster) {
    if (e.player >= o.players) return "--absent, --present, --watching: player " + std::to_string(e.player) + " is not below --players";
  }
  o.session.players = o.players;
  o.session.local_player = o.player;
  if (!o.reference) {
    if (const Result<void> checked = check_config(o.session); !checked.ok()) return checked.error().message();
  }
  return {};
}

// PLAYER@TICK of --absent, --present and --watching, in the order given.
void add_roster_option(CLI::App& app, const std::string& name, Presence presence, Options& o,
                       const std::string& description) {
  app.add_option_function<std::string>(
         name,
         [name, presence, &o](const std::string& spec) {
           const size_t at = spec.find('@');
           long long player = 0, tick = 0;
           if (at == std::string::npos || !cli::read_integer(spec.substr(0, at), 1, 15, player) ||
               !cli::read_integer(spec.substr(at + 1), 1, 1000000, tick)) {
             cli::refuse(name, "PLAYER@TICK (player 1..15, tick 1..1000000)", spec);
           }
           o.roster.push_back({tick, tick, static_cast<int>(player), presence});
         },
         description)
      ->type_name("P@TICK")
      ->trigger_on_parse();  // each occurrence in turn: the roster keeps the command line's order
}

// Parses argv into `o`: nullopt, or the exit status (--help, a usage error).
std::optional<int> parse_options(int argc, char** argv, Options& o) {
  CLI::App app("play one player of a session over ENet on 127.0.0.1", "bitstep peer");
  app.add_option("--scene", o.scene_path, "the scene")->type_name("SCENE")->required();
  app.add_option("--inputs", o.inputs, "the local player's script (--reference: every player's, in order)")
      ->type_name("FILE")
      ->allow_extra_args(false);
  app.add_option("--connect", o.connect, "a peer's address, 127.0.0.1:PORT")
      ->type_name("ADDRESS")
      ->allow_extra_args(false);
  cli::add_integer(app, "--player", 0, 15, o.player, "the local player (default 0)")->type_name("K");
  cli::add_integer(app, "--players", 1, 16, o.players, "players in the session (default 2)")->type_name("N");
  cli::add_integer(app, "--port", 1, 65535, o.port, "the local port")->type_name("P");
  cli::add_read(
      app, "--mode", "lockstep or rollback",
      [&o](const std::string& mode) {
        o.session.mode = mode == "lockstep" ? SessionMode::lockstep : SessionMode::rollback;
        return mode == "lockstep" || mode == "rollback";
      },
      "lockstep or rollback")
      ->type_name("MODE");
  cli::add_integer(app, "--delay", 0, 32, o.session.input_delay, "input delay in ticks")->type_name("D");
  cli::add_integer(app, "--max-prediction", 1, 64, o.session.max_prediction, "ticks a peer may run ahead")
      ->type_name("K");
  cli::add_integer(app, "--checksum-every", 1, 3600, o.session.checksum_interval, "ticks between checksums")
      ->type_name("K");
  cli::add_integer(app, "--ticks", 1, 1000000, o.ticks, "ticks to play (default 600)")->type_name("N");
  cli::add_integer(app, "--hz", 0, 1000, o.hz, "ticks per second (default 60; 0: as fast as it can)")
      ->type_name("F");
  cli::add_integer(app, "--timeout", 1, 3600, o.timeout_s, "seconds without progress before giving up (default 60)")
      ->type_name("S");
  cli::add_integer(app, "--loss", 0, 100, o.faults.loss_percent, "percent of packets dropped")->type_name("PCT");
  cli::add_integer(app, "--duplicate", 0, 100, o.faults.duplicate_percent, "percent of packets sent twice")
      ->type_name("PCT");
  cli::add_read(
      app, "--jitter", "MIN-MAX milliseconds (0..10000)",
      [&o](const std::string& range) {
        const size_t dash = range.find('-');
        long long lo = 0, hi = 0;
        if (dash == std::string::npos || !cli::read_integer(range.substr(0, dash), 0, 10000, lo) ||
            !cli::read_integer(range.substr(dash + 1), lo, 10000, hi)) {
          return false;
        }
        o.faults.min_delay_ms = static_cast<int>(lo);
        o.faults.max_delay_ms = static_cast<int>(hi);
        return true;
      },
      "each packet delayed MIN to MAX ms")
      ->type_name("MIN-MAX");
  cli::add_integer(app, "--seed", 0, INT64_MAX, o.faults.seed, "the faults' random seed")->type_name("S");
  cli::add_read(
      app, "--corrupt", "BODY@TICK",
      [&o](const std::string& spec) {
        const size_t at = spec.rfind('@');
        long long tick = 0;
        if (at == std::string::npos || at == 0 || !cli::read_integer(spec.substr(at + 1), 1, 1000000, tick)) {
          return false;
        }
        o.corrupt_body = spec.substr(0, at);
        o.corrupt_tick = tick;
        return true;
      },
      "nudge a body's velocity as a tick runs, each time it runs (a desync to be found)")
      ->type_name("BODY@TICK");
  app.add_flag("--join", o.session.joining, "play the match in progress in --player's slot");
  app.add_flag_callback(
      "--watch", [&o] { o.session.joining = o.session.watching = true; },
      "watch the match in progress in --player's slot");
  cli::add_integer(app, "--leave-after", 0, 100000, o.session.leave_after,
                   "the host marks a player silent this many frames absent")
      ->type_name("FRAMES");
  add_roster_option(app, "--absent", Presence::absent, o, "--reference: a player absent from TICK");
  add_roster_option(app, "--present", Presence::present, o, "--reference: a player present from TICK");
  add_roster_option(app, "--watching", Presence::watching, o, "--reference: a player watching from TICK");
  cli::add_integer(app, "--chain-from", 0, 1000000, o.chain_from, "--reference: the chain after TICK")
      ->type_name("TICK");
  app.add_flag("--json", o.json, "the report as JSON");
  app.add_flag("--reference", o.reference, "run every player's --inputs in one process (the chain peers must reach)");
  if (const std::optional<int> code = cli::parse(app, "peer", argc, argv)) return code;
  if (const std::string error = check_options(o); !error.empty()) {
    fmt::print(stderr, "bitstep peer: {}\n", error);
    return exit_code::usage;
  }
  return std::nullopt;
}

// A player's script: for each tick, its inputs (as a JSON array text).
using Script = std::map<int64_t, PlayerInput>;

Result<Script> read_script(const std::string& path, const Scene& scene, int delay) {
  const Result<InputsFile> loaded = load_inputs_file(path, scene);
  if (!loaded.ok()) return loaded.error();
  Script script;
  for (const Input& input : loaded->inputs) {
    // Each tick's inputs are read on their own, so a name an earlier tick
    // added is unknown to a later one.
    if (input.kind == Input::Kind::add_joint || input.kind == Input::Kind::remove_joint) {
      return Error{path + ": " + input.source.path, "a peer's input cannot add or remove joints"};
    }
    if (input.kind == Input::Kind::add_character || input.kind == Input::Kind::remove_character) {
      return Error{path + ": " + input.source.path, "a peer's input cannot add or remove characters"};
    }
    if (input.step <= delay) {
      return Error{path + ": " + input.source.path + ".step",
                   "within the input delay (" + std::to_string(delay) + " ticks)"};
    }
    PlayerInput& text = script[input.step];
    text += text.empty() ? "[" : ",";
    text += json::write(input.source);
  }
  for (auto& [tick, text] : script) text += "]";
  return script;
}

// The game of `bitstep peer`: a player's input is the list of replay
// inputs it applies at that tick ("impulse", "force", "drive", ...), read
// against the scene (every value inside the envelope) and applied.
ApplyInput scripted_game(const Scene& scene) {
  return [&scene](Simulation& sim, int player, const PlayerInput& input) {
    if (input.empty()) return;
    const Result<std::vector<Input>> parsed = parse_inputs(input, scene, "player " + std::to_string(player));
    if (!parsed.ok()) return;  // a peer's garbage: nothing happens, on every peer
    InputRun run(sim.world());
    apply_inputs(sim.world(), parsed.value(), static_cast<int64_t>(sim.tick()) + 1, run);
  };
}

// The game, and with --corrupt the cheat: one bit of the body's velocity
// flipped as the tick runs, each time it runs (a rollback runs it again):
// a world that computes differently from its peers'.
ApplyInput corrupted(ApplyInput game, const Options& o) {
  if (o.corrupt_body.empty()) return game;
  return [game = std::move(game), &o](Simulation& sim, int player, const PlayerInput& input) {
    game(sim, player, input);
    if (player != o.player || static_cast<int64_t>(sim.tick()) + 1 != o.corrupt_tick) return;
    if (const auto body = sim.find_body(o.corrupt_body)) {
      Vec3 v = sim.world().body(*body).linear_velocity;
      v.x = Fixed::from_raw(v.x.raw() ^ 1);
      sim.set_velocity(*body, v, sim.world().body(*body).angular_velocity);
    }
  };
}

// " (body "name")" for a difference at "$.bodies[N]..." of a named scene body.
std::string body_named(const Scene& scene, const std::string& difference) {
  const std::string prefix = "$.bodies[";
  if (difference.rfind(prefix, 0) != 0) return {};
  const size_t slot = std::strtoull(difference.c_str() + prefix.size(), nullptr, 10);
  if (slot >= scene.bodies.size() || scene.bodies[slot].name.empty()) return {};
  return " (body " + json::quote(scene.bodies[slot].name) + ")";
}

uint64_t chain_digest(const std::vector<uint64_t>& chain) {
  SplitMix64 mix{0};
  uint64_t digest = 0;
  for (const uint64_t h : chain) {
    mix.state = digest ^ h;
    digest = mix.next();
  }
  return digest;
}

// The roster changes a session applied, as the options that make
// --reference apply them.
std::string roster_options(const Session& session) {
  static const char* const names[] = {"absent", "present", "watching"};
  std::string changes;
  for (const RosterEvent& e : session.roster_log()) {
    changes += fmt::format("{}--{} {}@{}", changes.empty() ? "" : " ", names[static_cast<int>(e.presence)], e.player,
                           e.from);
  }
  return changes;
}

// `chain` holds the hashes after ticks first + 1, first + 2, ...
void report(const Options& o, int64_t first, const std::vector<uint64_t>& chain, const Session* session,
            const NetStats* net, double seconds) {
  const uint64_t final_hash = chain.empty() ? 0 : chain.back();
  const int64_t last = first + static_cast<int64_t>(chain.size());
  if (!o.json) {
    fmt::print("player {}: tick {} hash {:016x}, chain {:016x}", o.player, last, final_hash, chain_digest(chain));
    if (first > 0) fmt::print(" (from tick {})", first);
    if (session != nullptr) {
      const SessionStats& s = session->stats();
      fmt::print(" ({} rollbacks, {} ticks again, {} refused)", s.rollbacks, s.resimulated_ticks, s.refused_messages);
    }
    fmt::print(" in {:.1f} s\n", seconds);
    return;
  }
  fmt::print("{{\"player\": {}, \"ticks\": {}, \"first_tick\": {}, \"final_hash\": \"{:016x}\", \"chain\": \"{:016x}\", "
             "\"seconds\": {:.3f}",
             o.player, last, first, final_hash, chain_digest(chain), seconds);
  if (session != nullptr) {
    const SessionStats& s = session->stats();
    fmt::print(", \"rollbacks\": {}, \"resimulated_ticks\": {}, \"stalls\": {}, \"predicted_inputs\": {}, "
               "\"mispredicted_inputs\": {}, \"refused_messages\": {}",
               s.rollbacks, s.resimulated_ticks, s.stalls, s.predicted_inputs, s.mispredicted_inputs,
               s.refused_messages);
    fmt::print(", \"refused_states\": {}, \"roster\": \"{}\", \"links\": [", s.refused_states,
               roster_options(*session));
    const char* comma = "";
    for (int p = 0; p < o.players; ++p) {
      if (p == o.player) continue;
      const PeerStats l = session->peer_stats(p);
      fmt::print(
          "{}{{\"player\": {}, \"ping_frames\": {}, \"frames_ahead\": {}, \"messages_received\": {}, "
          "\"messages_lost\": {}, \"duplicates\": {}}}",
          comma, p, l.ping_frames, l.frames_ahead, l.messages_received, l.messages_lost, l.duplicates);
      comma = ", ";
    }
    fmt::print("]");
    if (const auto& d = session->desync()) {
      fmt::print(", \"desync\": {{\"tick\": {}, \"player\": {}, \"local\": \"{:016x}\", \"remote\": \"{:016x}\", "
                 "\"difference\": {}}}",
                 d->tick, d->player, d->local, d->remote, json::quote(d->difference));
    }
  }
  if (net != nullptr) {
    fmt::print(", \"packets_sent\": {}, \"packets_received\": {}, \"dropped\": {}, \"duplicated\": {}, "
               "\"stray_datagrams\": {}",
               net->sent, net->received, net->dropped, net->duplicated, net->stray);
  }
  fmt::print("}}\n");
}

// Every player's script in one simulation, in player order each tick.
int run_reference(const Options& o, const Scene& scene, Simulation sim) {
  std::vector<Script> scripts;
  for (const std::string& path : o.inputs) {
    Result<Script> script = read_script(path, scene, o.session.input_delay);
    if (!script.ok()) {
      fmt::print(stderr, "bitstep peer: {}\n", script.error().message());
      return exit_code::bad_input;
    }
    scripts.push_back(std::move(script).value());
  }
  // The roster a match made (replay/session.h): an absent player's input
  // is empty, and so is a joiner's for the input delay's ticks from its first.
  Roster roster(o.players);
  std::vector<int64_t> joined(static_cast<size_t>(o.players), 0);
  for (const RosterEvent& e : o.roster) {
    roster.set(e.player, e.from, e.presence);
    if (e.presence == Presence::present) joined[static_cast<size_t>(e.player)] = e.from;
  }
  const ApplyInput apply = scripted_game(scene);
  std::vector<uint64_t> chain;
  const auto start = std::chrono::steady_clock::now();
  for (int64_t t = 1; t <= o.ticks; ++t) {
    for (size_t p = 0; p < scripts.size(); ++p) {
      const int64_t since = joined[p];
      if (!roster.plays(static_cast<int>(p), t) || (since > 0 && t >= since && t < since + o.session.input_delay)) continue;
      const auto found = scripts[p].find(t);
      if (found != scripts[p].end()) apply(sim, static_cast<int>(p), found->second);
    }
    sim.step();
    if (t > o.chain_from) chain.push_back(sim.checksum());
  }
  report(o, o.chain_from, chain, nullptr, nullptr,
         std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace

int peer_command(int argc, char** argv) {
  Options o;
  if (const std::optional<int> code = parse_options(argc, argv, o)) return *code;
  Result<Simulation> sim = Simulation::from_file(o.scene_path);
  if (!sim.ok()) {
    fmt::print(stderr, "bitstep peer: {}\n", sim.error().message());
    return exit_code::bad_input;
  }
  const Scene scene = sim->scene();  // the inputs' names and materials (the session moves the simulation)
  if (o.reference) return run_reference(o, scene, std::move(*sim));

  Script script;
  if (!o.inputs.empty()) {
    Result<Script> read = read_script(o.inputs[0], scene, o.session.input_delay);
    if (!read.ok()) {
      fmt::print(stderr, "bitstep peer: {}\n", read.error().message());
      return exit_code::bad_input;
    }
    script = std::move(read).value();
  }
  const Hello hello{o.player,      o.players, o.session.mode, o.session.input_delay, sim->hash(), o.session.joining,
                    o.session.watching};
  Session session(std::move(*sim), o.session, corrupted(scripted_game(scene), o));

  std::unique_ptr<EnetTransport> net;
  std::map<uint32_t, int> player_of;  // identified ENet peers
  std::vector<bool> present(static_cast<size_t>(o.players), false);
  present[static_cast<size_t>(o.player)] = true;
  std::vector<bool> wants_in(static_cast<size_t>(o.players), false);  // the host: joiners not yet admitted ...
  std::vector<bool> wants_to_watch(static_cast<size_t>(o.players), false);  // ... and whether to watch
  bool started = o.session.joining;  // a match starts once every player said hello; a joiner's runs already
  uint64_t refused_packets = 0;
  bool refused_by = false;  // a peer refused our hello: this match is not ours to play
  if (o.players > 1) {
    std::string error;
    net = EnetTransport::open(static_cast<uint16_t>(o.port), o.faults, error);
    if (!net) {
      fmt::print(stderr, "bitstep peer: {}\n", error);
      return 1;
    }
    for (const std::string& target : o.connect) {
      if (!net->connect(target, error)) {
        fmt::print(stderr, "bitstep peer: {}\n", error);
        return 2;
      }
    }
  }
  EnetTransport::Handlers handlers;
  handlers.on_connect = [&](uint32_t peer) { net->send_to(peer, encode(hello)); };
  handlers.on_disconnect = [&](uint32_t peer) { player_of.erase(peer); };
  // A hello that does not fit: the peer is told why and we say it too. A
  // peer that knocked on our match is hung up on, and we play on; a match
  // we knocked on (--connect) is not ours to play: we stop (exit 6).
  const auto refuse = [&](uint32_t peer, HelloRefused why, const Hello& theirs, int their_version) {
    ++refused_packets;
    fmt::print(stderr, "bitstep peer: player {}: refused a hello from player {}: {}\n", o.player, theirs.player,
               describe(why, hello, packet_version(), theirs, their_version));
    net->send_to(peer, encode(Refusal{why, hello, packet_version()}));
    if (net->dialled(peer)) {
      refused_by = true;
    } else {
      net->disconnect_later(peer);
    }
  };
  handlers.on_packet = [&](uint32_t peer, std::span<const uint8_t> bytes) {
    const Result<Packet> decoded = decode(bytes);
    if (!decoded.ok()) {
      ++refused_packets;  // malformed, or another build's
      if (looks_like_hello(bytes) && packet_version(bytes) != packet_version()) {
        refuse(peer, HelloRefused::version, Hello{}, packet_version(bytes));
      }
      return;
    }
    const Packet& packet = decoded.value();
    if (const auto* refusal = std::get_if<Refusal>(&packet)) {
      fmt::print(stderr, "bitstep peer: player {}: player {} refused our hello: {}\n", o.player,
                 refusal->refuser.player,
                 describe(refusal->reason, refusal->refuser, refusal->version, hello, packet_version()));
      if (net->dialled(peer)) refused_by = true;  // its match, not ours (one that knocked on ours hears why and stops)
      return;
    }
    if (const auto* theirs = std::get_if<Hello>(&packet)) {
      const bool said_hello =
          theirs->player >= 0 && theirs->player < o.players && present[static_cast<size_t>(theirs->player)];
      if (const std::optional<HelloRefused> why = refusal_of(hello, *theirs, said_hello)) {
        refuse(peer, *why, *theirs, packet_version());
        return;
      }
      player_of[peer] = theirs->player;
      present[static_cast<size_t>(theirs->player)] = true;
      if (theirs->joining) wants_in[static_cast<size_t>(theirs->player)] = true;
      wants_to_watch[static_cast<size_t>(theirs->player)] = theirs->watching;
      return;
    }
    const auto* message = std::get_if<SessionMessage>(&packet);
    const auto who = player_of.find(peer);
    if (message == nullptr || who == player_of.end() || who->second != message->player) {
      ++refused_packets;  // from a peer that did not say who it is, or as someone else
      return;
    }
    session.receive(*message);
  };

  std::vector<uint64_t> chain;
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const auto frame = std::chrono::duration<double>(o.hz > 0 ? 1.0 / o.hz : 0.0);
  auto next_frame = std::chrono::steady_clock::now();
  double finished_at = -1;
  while (true) {
    if (elapsed() > o.timeout_s) {
      fmt::print(stderr, "bitstep peer: player {}: timed out after {:.0f} s at tick {} (confirmed {}, {} refused{}{})\n",
                 o.player, o.timeout_s, session.tick(), session.confirmed_tick(), session.stats().refused_messages,
                 session.roster_log().empty() ? "" : "; roster ", roster_options(session));
      return 1;
    }
    if (net) net->poll(1, handlers);
    if (refused_by) {
      net->flush();  // our refusal, if we sent one, on its way
      return exit_code::refused;
    }
    started = started || std::all_of(present.begin(), present.end(), [](bool p) { return p; });
    for (int p = 0; p < o.players; ++p) {  // the host lets a joiner in once its slot is free
      const size_t k = static_cast<size_t>(p);
      if (wants_in[k] && session.admit(p, wants_to_watch[k])) wants_in[k] = false;
    }
    if (started && std::chrono::steady_clock::now() >= next_frame) {
      next_frame += std::chrono::duration_cast<std::chrono::steady_clock::duration>(frame);
      // One input per tick, as a game's frame gives it: never more than the
      // input delay ahead of the simulation.
      const bool due = session.local_input_tick() < std::min(o.ticks, session.tick() + o.session.input_delay + 1) ||
                       (session.roster_waits() && session.local_input_tick() < o.ticks);
      if (session.joined() && due) {
        const int64_t t = session.local_input_tick() + 1;
        const auto found = script.find(t);
        session.add_local_input(found == script.end() ? PlayerInput{} : found->second);
      }
      if (session.tick() < o.ticks) session.advance();
      if (session.tick() >= o.ticks) session.heartbeat();
      // The time sync's advice: this peer runs ahead, so it idles that many frames.
      for (const SessionEvent& e : session.take_events()) {
        if (e.kind == SessionEvent::Kind::wait_recommended && o.hz > 0) {
          next_frame += std::chrono::duration_cast<std::chrono::steady_clock::duration>(frame * e.frames);
        }
      }
    }
    for (const SessionMessage& m : session.take_outgoing()) {
      const bool reliable = m.kind == SessionMessage::Kind::state || m.kind == SessionMessage::Kind::join_state;
      if (net) net->send_all(encode(m), reliable);
    }
    const int64_t first = session.first_tick();
    while (session.joined() && first + static_cast<int64_t>(chain.size()) < std::min(session.confirmed_tick(), o.ticks)) {
      chain.push_back(*session.confirmed_hash(first + static_cast<int64_t>(chain.size()) + 1));
    }
    bool acked = session.joined() && first + static_cast<int64_t>(chain.size()) >= o.ticks;
    for (int p = 0; p < o.players && acked; ++p) {
      acked = p == o.player || !session.roster().follows(p) || session.peer_ack(p) >= o.ticks;
    }
    const bool desync_named = session.desync() && !session.desync()->difference.empty();
    if ((acked || desync_named) && finished_at < 0) finished_at = elapsed();
    // Linger a little: a peer whose last message was lost hears our ack again.
    if (finished_at >= 0 && elapsed() - finished_at > 0.3) break;
    if (!started || session.tick() >= o.ticks) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (o.json) {
    report(o, session.first_tick(), chain, &session, net ? &net->stats() : nullptr, elapsed());
  } else {
    report(o, session.first_tick(), chain, &session, nullptr, elapsed());
  }
  if (refused_packets > 0) fmt::print(stderr, "bitstep peer: player {}: {} packets refused\n", o.player, refused_packets);
  if (const auto& d = session.desync()) {
    fmt::print(stderr, "bitstep peer: player {}: desync at tick {} with player {}: {}{}\n", o.player, d->tick, d->player,
               d->difference, body_named(scene, d->difference));
    return exit_code::desync;
  }
  return 0;
}

}  // namespace bitstep
