// `bitstep peer`: one player of a session (replay/session.h) over ENet on
// 127.0.0.1, its inputs from a script; or, with --reference, every
// player's script in one process without a network (the chain the peers
// must reach).
#pragma once

namespace bitstep {

int peer_command(int argc, char** argv);

}  // namespace bitstep
