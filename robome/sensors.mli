(** The sensors of the robot and of its phone, as pure functions of the
    robot's state and the world (the simulation decides when they sample and
    what the host makes of a reading).

    - the robot's front proximity sensor: the nearest obstacle (wall or cube
      side) in a cone ahead of the body, reported as a distance band;
    - the robot's edge detector: is the floor missing just ahead?
    - the phone's UWB positioning: the true position plus Gaussian noise;
    - the phone's front camera: which QR codes are decodable now;
    - the phone's accelerometer and gyroscope: is the robot tipping or
      falling ({!Robot.tipping}, {!Robot.fallen}). *)

val nearest_ahead : Robot.t -> float option
(** The distance from the front of the body to the nearest wall or cube side
    inside the proximity cone (five rays across it), if within the last band. *)

val proximity_band : Params.t -> float option -> float option
(** The smallest band not below the distance: [Some 0.2], [Some 0.5],
    [Some 1.0] (with the default bands) or [None]. *)

val edge_ahead : Robot.t -> bool
(** Is the floor point [edge_lookahead] ahead of the body's front over a
    drop-off? *)

val gaussian : Random.State.t -> float
(** A standard normal sample (Box-Muller). *)

val uwb : Random.State.t -> sigma:float -> Robot.t -> float * float
(** The measured position: the true centre plus independent N(0, sigma^2)
    noise on each axis. With sigma = 0.3 m the radial error is under 1 m
    with probability 1 - exp(-1/(2 sigma^2)) > 0.99, as the paper reports
    for the SpoonPhone. *)

type sighting = {
  cube : int;        (** index in {!World.t.cubes} *)
  face : int;        (** 0-3 *)
  text : string;
  distance : float;  (** m, from the camera to the face centre on the floor plan *)
}

val readable : Robot.t -> sighting list
(** The QR codes the camera can decode now, by cube then face. A face is
    readable when it carries a text and: its distance is at least
    [camera_min_range] and at most [qr_range_factor] times the code's side;
    its centre is inside the horizontal and vertical fields of view (the
    vertical one follows the head's tilt and the camera's height); the face
    looks towards the camera within [qr_max_view_angle]; and the line of
    sight to its centre crosses no other cube and no extra wall. A fallen
    robot reads nothing. *)
