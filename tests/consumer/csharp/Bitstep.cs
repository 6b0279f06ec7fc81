// A C# binding of bitstep's C API (replay/bitstep.h and
// replay/bitstep_session.h) by P/Invoke against the shared library
// (libbitstep.so): the part a rollback game over the network uses. The
// structs are the C ones, field for field (enumerations are int fields);
// numbers are Q32.32 in a long, converted by the library, never by a float.
using System;
using System.Runtime.InteropServices;

namespace Bitstep {

public enum Status { Ok = 0, Invalid = 1, NotFound = 2, BufferTooSmall = 3, NullArgument = 4, OutOfMemory = 5, NotReady = 6 }

[StructLayout(LayoutKind.Sequential)] public struct Vec3 { public long X, Y, Z; }
[StructLayout(LayoutKind.Sequential)] public struct Quat { public long W, X, Y, Z; }
[StructLayout(LayoutKind.Sequential)] public struct Pose { public Vec3 Position; public Quat Orientation; }
[StructLayout(LayoutKind.Sequential)] public struct Body { public uint Index, Generation; }
[StructLayout(LayoutKind.Sequential)] public struct Joint { public uint Index, Generation; }

public enum EventType { ContactBegin = 0, ContactEnd = 1, SensorBegin = 2, SensorEnd = 3, LeftWorld = 4, JointBroken = 5 }
[StructLayout(LayoutKind.Sequential)]
public struct Event { public int Type; public Body BodyA, BodyB; public uint ShapeA, ShapeB; public Joint Joint; }

[StructLayout(LayoutKind.Sequential)]
public struct SessionConfig {
  public int Players, LocalPlayer, Mode, InputDelay, MaxPrediction, ChecksumInterval, LeaveAfter, Joining, Watching,
      InterruptAfter;
}

[StructLayout(LayoutKind.Sequential)]
public struct SessionStats {
  public long Rollbacks, ResimulatedTicks, Stalls, PredictedInputs, MispredictedInputs, RefusedMessages, RefusedStates,
      DroppedEvents;
}

[StructLayout(LayoutKind.Sequential)]
public struct PeerStats { public int PingFrames, FramesAhead; public long FramesSilent, PacketsReceived, PacketsLost, Duplicates; }

// The game's hooks as the C API calls them (cdecl function pointers).
[UnmanagedFunctionPointer(CallingConvention.Cdecl)]
public delegate void ApplyHook(IntPtr user, IntPtr sim, int player, IntPtr input, UIntPtr size);
[UnmanagedFunctionPointer(CallingConvention.Cdecl)]
public delegate void AdvanceHook(IntPtr user, IntPtr sim, long tick);
[UnmanagedFunctionPointer(CallingConvention.Cdecl)]
public delegate UIntPtr SaveHook(IntPtr user, IntPtr buffer, UIntPtr capacity);
[UnmanagedFunctionPointer(CallingConvention.Cdecl)]
public delegate int LoadHook(IntPtr user, IntPtr state, UIntPtr size);

[StructLayout(LayoutKind.Sequential)]
public struct GameHooks { public IntPtr User, Apply, Advance, Save, Load; }

public static class Native {
  const string Library = "bitstep";

  [DllImport(Library)] public static extern long bitstep_fixed_from_int(int value);
  [DllImport(Library)] public static extern Status bitstep_fixed_from_ratio(long numerator, long denominator, out long value);
  [DllImport(Library)]
  public static extern Status bitstep_create_from_file(string path, out IntPtr sim, byte[] error, UIntPtr capacity);
  [DllImport(Library)] public static extern void bitstep_destroy(IntPtr sim);
  [DllImport(Library)] static extern IntPtr bitstep_last_error(IntPtr sim);
  public static string LastError(IntPtr sim) { return Marshal.PtrToStringAnsi(bitstep_last_error(sim)); }
  [DllImport(Library)] public static extern Status bitstep_find_body(IntPtr sim, string name, out Body body);
  [DllImport(Library)] public static extern Status bitstep_set_events(IntPtr sim, int on);
  [DllImport(Library)]
  public static extern Status bitstep_get_events(IntPtr sim, [Out] Event[] events, UIntPtr capacity, out UIntPtr count);
  [DllImport(Library)] public static extern Status bitstep_get_pose(IntPtr sim, Body body, out Pose pose);
  [DllImport(Library)]
  public static extern Status bitstep_apply_impulse(IntPtr sim, Body body, Vec3 impulse, Vec3 point);
  [DllImport(Library)] public static extern Status bitstep_step(IntPtr sim);
  [DllImport(Library)] public static extern ulong bitstep_checksum(IntPtr sim);

  [DllImport(Library)] public static extern SessionConfig bitstep_default_session_config();
  [DllImport(Library)]
  public static extern Status bitstep_session_create(ref IntPtr sim, ref SessionConfig config, ref GameHooks hooks,
                                                     out IntPtr session);
  [DllImport(Library)] public static extern void bitstep_session_destroy(IntPtr session);
  [DllImport(Library)] static extern IntPtr bitstep_session_last_error(IntPtr session);
  public static string SessionLastError(IntPtr session) {
    return Marshal.PtrToStringAnsi(bitstep_session_last_error(session));
  }
  [DllImport(Library)]
  public static extern Status bitstep_session_add_local_input(IntPtr session, byte[] input, UIntPtr size);
  [DllImport(Library)] public static extern Status bitstep_session_advance(IntPtr session);
  [DllImport(Library)] public static extern Status bitstep_session_receive(IntPtr session, IntPtr packet, UIntPtr size);
  [DllImport(Library)]
  public static extern Status bitstep_session_take_packet(IntPtr session, byte[] buffer, UIntPtr capacity,
                                                          out UIntPtr size, out int reliable);
  [DllImport(Library)] public static extern Status bitstep_session_heartbeat(IntPtr session);
  [DllImport(Library)] public static extern long bitstep_session_tick(IntPtr session);
  [DllImport(Library)] public static extern long bitstep_session_confirmed_tick(IntPtr session);
  [DllImport(Library)]
  public static extern Status bitstep_session_confirmed_checksum(IntPtr session, long tick, out ulong checksum);
  [DllImport(Library)]
  public static extern ulong bitstep_session_tick_checksum(ulong world, byte[] game, UIntPtr size);
  [DllImport(Library)] public static extern Status bitstep_session_get_stats(IntPtr session, out SessionStats stats);
  [DllImport(Library)]
  public static extern Status bitstep_session_get_peer_stats(IntPtr session, int player, out PeerStats stats);
}

}
