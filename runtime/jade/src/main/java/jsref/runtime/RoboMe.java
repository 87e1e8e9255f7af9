package jsref.runtime;

import java.util.ArrayList;
import java.util.Collections;
import java.util.List;

/** The host object {@code @robome} of the command line: it records the
    RoboMe SDK calls the paper's agent invokes (the methods of the paper's
    Android application), and does nothing else. As the reference's, each
    method takes any arguments and returns nothing. Shown in traces as
    {@code <RoboMe>}. */
public final class RoboMe {
  private final List<String> calls = Collections.synchronizedList(new ArrayList<>());

  /** The calls so far, in order (static, so that Jadescript code cannot
      invoke it: the object offers the SDK's methods only).
      @param r the host object @return the methods' names */
  public static List<String> callsOf(RoboMe r) { synchronized (r.calls) { return new ArrayList<>(r.calls); } }

  /** Starts listening to the robot's sensors. @param args ignored */
  public void startListening(Object... args) { calls.add("startListening"); }
  /** Stops the robot. @param args ignored */
  public void callStop(Object... args) { calls.add("callStop"); }
  /** Moves forward. @param args ignored */
  public void callMoveForward(Object... args) { calls.add("callMoveForward"); }
  /** Moves backward. @param args ignored */
  public void callMoveBackward(Object... args) { calls.add("callMoveBackward"); }
  /** Turns left. @param args ignored */
  public void callTurnLeft(Object... args) { calls.add("callTurnLeft"); }
  /** Turns right. @param args ignored */
  public void callTurnRight(Object... args) { calls.add("callTurnRight"); }
  /** Tilts the head up. @param args ignored */
  public void callHeadTiltUp(Object... args) { calls.add("callHeadTiltUp"); }
  /** Tilts the head down. @param args ignored */
  public void callHeadTiltDown(Object... args) { calls.add("callHeadTiltDown"); }
  /** Resets the head. @param args ignored */
  public void callHeadReset(Object... args) { calls.add("callHeadReset"); }
}
