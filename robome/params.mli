(** The physical parameters of the simulated RoboMe and of the SpoonPhone
    mounted in its head cradle, in one record.

    Units: metres, seconds and radians throughout (the doc comment of each
    field says which).

    {b Where the values come from.} The paper (Section 5) gives only the
    shape of the hardware: a small toy robot with two slow wheels, one front
    proximity sensor, a tilting head cradle holding the phone, commands and
    proximity alerts exchanged as sounds over the headset cable, and UWB
    positioning with an error under 1 m. WowWee's RoboMe Android SDK
    (github.com/WowWeeLabs/RoboMe-Android-SDK) fixes the command set: stop,
    move forward and backward at speed levels 1-5, turn left and right at
    speed levels 1-5 or by 90, 180 and 360 degrees, head tilt up, down and
    reset, each played as a short WAV tone. WowWee publishes no speeds, turn
    rates or sensor ranges, so every number below is an {e assumption}
    chosen to be plausible for a toy of this size (about 20 cm wide and
    33 cm tall, a top speed well under a walking pace); the proximity bands
    (about 20, 50 and 100 cm) and the 100 ms gap between sounds (the Android
    SDK's default) are those docs/simulation.md states. Change them here or
    per scenario, never in the code. *)

type t = {
  body_radius : float;
      (** m; the body is a disc for collisions (0.10: a body about 20 cm wide) *)
  forward_speeds : float array;
      (** m/s at speed levels 1-5 (0.04 .. 0.16) *)
  backward_speeds : float array;
      (** m/s at speed levels 1-5, a positive magnitude (0.03 .. 0.12) *)
  turn_rates : float array;
      (** rad/s of an on-the-spot turn at speed levels 1-5 (30 .. 90 deg/s) *)
  angle_turn_rate : float;
      (** rad/s of the preset 90/180/360 degree turns (60 deg/s) *)
  sound_duration : float;
      (** s; how long one command tone lasts; the robot acts when it has
          heard the whole tone (0.10) *)
  sound_gap : float;
      (** s; silence between two tones (0.10, the SDK's default) *)
  alert_latency : float;
      (** s; from a proximity change to the phone decoding the robot's alert
          tone (0.10, one tone) *)
  proximity_bands : float array;
      (** m; the distances the front sensor can report, nearest first
          ([|0.2; 0.5; 1.0|]); beyond the last one it reports nothing *)
  proximity_half_angle : float;
      (** rad; half the opening of the proximity sensor's cone (15 deg) *)
  edge_lookahead : float;
      (** m; the edge detector looks at the floor this far ahead of the
          body's front (0.05) *)
  camera_height : float;
      (** m above the floor (0.30: the phone sits in the head cradle) *)
  camera_hfov : float;  (** rad; horizontal field of view (60 deg) *)
  camera_vfov : float;  (** rad; vertical field of view (45 deg) *)
  camera_min_range : float;  (** m; closer than this the code is out of focus (0.15) *)
  qr_range_factor : float;
      (** a code is decodable up to this many times its side (8.0) *)
  qr_fraction : float;
      (** side of a QR code as a fraction of the cube face's side (0.8) *)
  qr_max_view_angle : float;
      (** rad; a face seen more obliquely than this is not decodable (60 deg) *)
  camera_latency : float;  (** s; from the frame to the decoded text (0.05) *)
  head_up_angle : float;  (** rad; camera pitch with the head tilted up (+20 deg) *)
  head_down_angle : float;  (** rad; camera pitch with the head tilted down (-30 deg) *)
  speed_noise : float;
      (** relative standard deviation of the actual wheel speed: each motion
          command's speed (and a preset turn's rate) is the nominal one times
          [1 + speed_noise * N(0,1)] (0.03; toy gear motors are imprecise) *)
  drift : float;
      (** rad/s; standard deviation of the heading drift while driving
          (unequal wheels), drawn per motion command (1 deg/s) *)
}

val default : t
(** The values listed above. *)

val noiseless : t -> t
(** The same parameters without motion noise (for closed-form tests). *)

val deg : float -> float
(** Degrees to radians. *)

val to_deg : float -> float
(** Radians to degrees. *)
