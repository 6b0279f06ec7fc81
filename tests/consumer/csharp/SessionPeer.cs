// tests/consumer/session_peer.c's game in C#, through the binding in
// Bitstep.cs, over ENet (Debian's libenet7, by P/Invoke): the same
// arguments, the same packets and the same final line, so a C peer and a C#
// peer play one match (tools/check_package.sh).
//
//   mono SessionPeer.exe SCENE PLAYER PORT PEER_PORT TICKS LOSS
//   mono SessionPeer.exe SCENE reference TICKS
using System;
using System.Runtime.InteropServices;
using Bitstep;

static class Enet {
  const string Library = "libenet.so.7";
  public const int Connect = 1, Disconnect = 2, Receive = 3;
  public const uint Reliable = 1, Unsequenced = 2;

  [StructLayout(LayoutKind.Sequential)] public struct Address { public uint Host; public ushort Port; }
  [StructLayout(LayoutKind.Sequential)]
  public struct Event { public int Type; public IntPtr Peer; public byte ChannelId; public uint Data; public IntPtr Packet; }

  [DllImport(Library)] public static extern int enet_initialize();
  [DllImport(Library)] public static extern void enet_deinitialize();
  [DllImport(Library)] public static extern int enet_address_set_host(ref Address address, string host);
  [DllImport(Library)]
  public static extern IntPtr enet_host_create(ref Address address, UIntPtr peers, UIntPtr channels, uint down, uint up);
  [DllImport(Library)]
  public static extern IntPtr enet_host_connect(IntPtr host, ref Address address, UIntPtr channels, uint data);
  [DllImport(Library)] public static extern int enet_host_service(IntPtr host, out Event e, uint timeout);
  [DllImport(Library)] public static extern void enet_host_flush(IntPtr host);
  [DllImport(Library)] public static extern void enet_host_destroy(IntPtr host);
  [DllImport(Library)] public static extern IntPtr enet_packet_create(byte[] data, UIntPtr length, uint flags);
  [DllImport(Library)] public static extern void enet_packet_destroy(IntPtr packet);
  [DllImport(Library)] public static extern int enet_peer_send(IntPtr peer, byte channel, IntPtr packet);

  // An ENetPacket's data and dataLength (enet/enet.h, 64-bit: after
  // referenceCount and flags, at bytes 16 and 24).
  public static IntPtr Data(IntPtr packet) { return Marshal.ReadIntPtr(packet, 16); }
  public static UIntPtr Length(IntPtr packet) { return (UIntPtr)(ulong)Marshal.ReadInt64(packet, 24); }
}

class Game {
  public int[] Health = {100, 100};
  public int[] Score = {0, 0};
  public Body[] Balls = new Body[2];
  readonly Event[] events = new Event[64];

  static void Check(Status status, IntPtr sim, string what) {
    if (status == Status.Ok) return;
    Console.Error.WriteLine("SessionPeer: " + what + ": " + (sim != IntPtr.Zero ? Native.LastError(sim) : status.ToString()));
    Environment.Exit(1);
  }

  // Which way a player pushes at a tick: 0 none, 1 toward +x, 2 toward -x.
  public static byte InputOf(int player, long tick) {
    long phase = (tick * (player + 2)) / (15 + 25 * player);
    return (byte)((phase + player) % 3);
  }

  public void Apply(IntPtr sim, int player, byte input) {
    if (input == 0) return;
    Pose pose;
    Check(Native.bitstep_get_pose(sim, Balls[player], out pose), sim, "get_pose");
    var push = new Vec3 { X = Native.bitstep_fixed_from_int(input == 1 ? 400 : -400) };
    Check(Native.bitstep_apply_impulse(sim, Balls[player], push, pose.Position), sim, "apply_impulse");
  }

  // A ball that meets the other scores; one that meets a wall loses 7 health.
  public void Advance(IntPtr sim) {
    UIntPtr count;
    Check(Native.bitstep_get_events(sim, events, (UIntPtr)events.Length, out count), sim, "get_events");
    for (int i = 0; i < (int)(ulong)count; ++i) {
      Event e = events[i];
      if (e.Type != (int)EventType.ContactBegin) continue;
      bool meet = e.BodyA.Index == Balls[0].Index && e.BodyB.Index == Balls[1].Index;
      for (int p = 0; p < 2; ++p) {
        uint mine = Balls[p].Index;
        if (e.BodyA.Index != mine && e.BodyB.Index != mine) continue;
        if (meet) {
          Score[p] += 1;
        } else if (e.BodyA.Index != 0 && e.BodyB.Index != 0) {  // slot 0 is the ground
          Health[p] -= 7;
        }
      }
    }
  }

  // Four little-endian int32: health 0 and 1, score 0 and 1 (the C game's bytes).
  public byte[] Save() {
    var bytes = new byte[16];
    int[] fields = {Health[0], Health[1], Score[0], Score[1]};
    for (int i = 0; i < 4; ++i) BitConverter.GetBytes(fields[i]).CopyTo(bytes, 4 * i);
    return bytes;
  }

  public bool Load(byte[] bytes) {
    if (bytes.Length != 16) return false;
    Health[0] = BitConverter.ToInt32(bytes, 0);
    Health[1] = BitConverter.ToInt32(bytes, 4);
    Score[0] = BitConverter.ToInt32(bytes, 8);
    Score[1] = BitConverter.ToInt32(bytes, 12);
    return true;
  }

  public IntPtr Arena(string scene) {
    IntPtr sim;
    var error = new byte[256];
    if (Native.bitstep_create_from_file(scene, out sim, error, (UIntPtr)error.Length) != Status.Ok) {
      Console.Error.WriteLine("SessionPeer: " + System.Text.Encoding.ASCII.GetString(error).TrimEnd('\0'));
      Environment.Exit(1);
    }
    Check(Native.bitstep_find_body(sim, "ball0", out Balls[0]), sim, "find_body");
    Check(Native.bitstep_find_body(sim, "ball1", out Balls[1]), sim, "find_body");
    Check(Native.bitstep_set_events(sim, 1), sim, "set_events");
    return sim;
  }

  public string Result(long ticks, ulong checksum) {
    return string.Format("tick {0} checksum {1:x16} score {2} {3} health {4} {5}", ticks, checksum, Score[0], Score[1],
                         Health[0], Health[1]);
  }
}

static class SessionPeer {
  static Game game = new Game();
  // The delegates the library calls: kept here, so the collector leaves them.
  static ApplyHook apply = (user, sim, player, input, size) => {
    if ((ulong)size == 1) game.Apply(sim, player, Marshal.ReadByte(input));
  };
  static AdvanceHook advance = (user, sim, tick) => game.Advance(sim);
  static SaveHook save = (user, buffer, capacity) => {
    byte[] bytes = game.Save();
    if ((ulong)capacity >= (ulong)bytes.Length) Marshal.Copy(bytes, 0, buffer, bytes.Length);
    return (UIntPtr)bytes.Length;
  };
  static LoadHook load = (user, state, size) => {
    var bytes = new byte[(int)(ulong)size];
    Marshal.Copy(state, bytes, 0, bytes.Length);
    return game.Load(bytes) ? 1 : 0;
  };

  static int Reference(string scene, long ticks) {
    IntPtr sim = game.Arena(scene);
    ulong checksum = 0;
    for (long t = 1; t <= ticks; ++t) {
      for (int p = 0; p < 2; ++p) game.Apply(sim, p, Game.InputOf(p, t));
      Native.bitstep_step(sim);
      game.Advance(sim);
      byte[] state = game.Save();
      checksum = Native.bitstep_session_tick_checksum(Native.bitstep_checksum(sim), state, (UIntPtr)state.Length);
    }
    Console.WriteLine(game.Result(ticks, checksum));
    Native.bitstep_destroy(sim);
    return 0;
  }

  static int Play(string scene, int player, int port, int peerPort, long ticks, int loss) {
    IntPtr sim = game.Arena(scene);
    SessionConfig config = Native.bitstep_default_session_config();
    config.Players = 2;
    config.LocalPlayer = player;
    config.Mode = 1;  // rollback
    var hooks = new GameHooks {
      Apply = Marshal.GetFunctionPointerForDelegate(apply),
      Advance = Marshal.GetFunctionPointerForDelegate(advance),
      Save = Marshal.GetFunctionPointerForDelegate(save),
      Load = Marshal.GetFunctionPointerForDelegate(load),
    };
    IntPtr session;
    if (Native.bitstep_session_create(ref sim, ref config, ref hooks, out session) != Status.Ok) {
      Console.Error.WriteLine("SessionPeer: session_create: " + Native.LastError(sim));
      return 1;
    }
    if (Enet.enet_initialize() != 0) return 1;
    var bound = new Enet.Address();
    Enet.enet_address_set_host(ref bound, "127.0.0.1");
    bound.Port = (ushort)port;
    var address = bound;
    address.Port = (ushort)peerPort;
    IntPtr host = Enet.enet_host_create(ref bound, (UIntPtr)1, (UIntPtr)1, 0, 0);
    if (host == IntPtr.Zero) {
      Console.Error.WriteLine("SessionPeer: cannot bind 127.0.0.1:" + port);
      return 1;
    }
    IntPtr peer = IntPtr.Zero;
    bool dialling = false;
    ulong random = (ulong)player + 1;
    var buffer = new byte[1 << 20];
    var input = new byte[1];
    long nextInput = 1, doneAt = -1;
    // 1 ms frames, for at most 60 s; half a second of heartbeats at the end.
    for (long frame = 0; frame < 60000; ++frame) {
      // Player 1 dials, and again when ENet gives an attempt up (session_peer.c's rule).
      if (player == 1 && !dialling && peer == IntPtr.Zero) {
        dialling = Enet.enet_host_connect(host, ref address, (UIntPtr)1, 0) != IntPtr.Zero;
      }
      Enet.Event e;
      // Up to 1 ms for the first event, then what is there (session_peer.c's rule).
      for (uint wait = frame == 0 ? 10u : 1u; Enet.enet_host_service(host, out e, wait) > 0; wait = 0) {
        if (e.Type == Enet.Connect) peer = e.Peer;
        if (e.Type == Enet.Disconnect) {
          peer = IntPtr.Zero;
          dialling = false;
        }
        if (e.Type == Enet.Receive) {
          Native.bitstep_session_receive(session, Enet.Data(e.Packet), Enet.Length(e.Packet));
          Enet.enet_packet_destroy(e.Packet);
        }
      }
      if (peer == IntPtr.Zero) continue;
      if (nextInput <= ticks) {
        input[0] = Game.InputOf(player, nextInput);
        if (Native.bitstep_session_add_local_input(session, input, (UIntPtr)1) == Status.Ok) ++nextInput;
      } else {
        Native.bitstep_session_heartbeat(session);
      }
      while (Native.bitstep_session_advance(session) == Status.Ok && Native.bitstep_session_tick(session) < nextInput - 1) {
      }
      UIntPtr size;
      int reliable;
      while (Native.bitstep_session_take_packet(session, buffer, (UIntPtr)buffer.Length, out size, out reliable) ==
             Status.Ok) {
        random = random * 6364136223846793005UL + 1442695040888963407UL;  // session_peer.c's generator
        if (reliable == 0 && (int)((random >> 33) % 100) < loss) continue;
        var bytes = new byte[(int)(ulong)size];
        Array.Copy(buffer, bytes, bytes.Length);
        Enet.enet_peer_send(peer, 0,
                            Enet.enet_packet_create(bytes, size, reliable != 0 ? Enet.Reliable : Enet.Unsequenced));
      }
      if (doneAt < 0 && Native.bitstep_session_confirmed_tick(session) >= ticks) doneAt = frame;
      if (doneAt >= 0 && frame - doneAt > 500) break;
    }
    Enet.enet_host_flush(host);
    ulong checksum;
    if (Native.bitstep_session_confirmed_checksum(session, ticks, out checksum) != Status.Ok) {
      Console.Error.WriteLine("SessionPeer: player " + player + ": tick " + ticks + " not confirmed");
      return 1;
    }
    SessionStats stats;
    PeerStats link;
    Native.bitstep_session_get_stats(session, out stats);
    Native.bitstep_session_get_peer_stats(session, 1 - player, out link);
    Console.Error.WriteLine(string.Format("player {0} (C#): {1} rollbacks, {2} ticks re-run, {3} of {4} packets from the peer lost, ping {5} frames",
                                          player, stats.Rollbacks, stats.ResimulatedTicks, link.PacketsLost,
                                          link.PacketsReceived + link.PacketsLost, link.PingFrames));
    Console.WriteLine(game.Result(ticks, checksum));
    Enet.enet_host_destroy(host);
    Enet.enet_deinitialize();
    Native.bitstep_session_destroy(session);
    return 0;
  }

  static int Main(string[] args) {
    if (args.Length == 3 && args[1] == "reference") return Reference(args[0], long.Parse(args[2]));
    if (args.Length == 6) {
      return Play(args[0], int.Parse(args[1]), int.Parse(args[2]), int.Parse(args[3]), long.Parse(args[4]),
                  int.Parse(args[5]));
    }
    Console.Error.WriteLine("usage: SessionPeer.exe SCENE PLAYER PORT PEER_PORT TICKS LOSS | SessionPeer.exe SCENE reference TICKS");
    return 2;
  }
}
