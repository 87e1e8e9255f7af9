(** The geometry of the world the robot moves in: a rectangular corridor
    (the floor is [[0, length] x [0, width]], walled on all four sides),
    extra wall segments inside it, cubes carrying a QR code on each side
    face, and drop-off regions where the floor ends (a stairwell, a step).
    Metres and radians; the frame is that of {!Kinematics}. *)

type point = { px : float; py : float }

type segment = { a : point; b : point }

type cube = {
  id : string;
  cx : float;
  cy : float;
  size : float;           (** side, m; the cube is [size] high too *)
  yaw : float;            (** rad; rotation of the cube about its vertical axis *)
  faces : string array;
      (** the QR texts of the four side faces, in the cube's own frame:
          +x (east at yaw 0), +y (north), -x (west), -y (south); an empty
          text is a face without a code *)
}

type rect = { x_min : float; y_min : float; x_max : float; y_max : float }

type broad
(** What {!disc_collides} looks at first (the bounding boxes of the walls and
    the circles round the cubes) and the sides of each cube for {!ray}, all
    derived from the walls and cubes by {!make}. *)

type t = {
  length : float;
  width : float;
  walls : segment list;     (** the four corridor walls first, then the extra ones *)
  cubes : cube array;
  dropoffs : rect list;
  broad : broad;            (** from [walls] and [cubes]; build a world with {!make} *)
}

val make : length:float -> width:float -> ?extra_walls:segment list -> cubes:cube list ->
  dropoffs:rect list -> unit -> t

val face_centre : cube -> int -> point
(** The centre of face [i] (0-3), on the floor plan. *)

val face_normal : cube -> int -> point
(** The outward unit normal of face [i]. *)

val face_centre_of : t -> int -> int -> point
(** [face_centre_of w j i = face_centre w.cubes.(j) i], computed once by
    {!make}. *)

val face_normal_of : t -> int -> int -> point
(** [face_normal_of w j i = face_normal w.cubes.(j) i], computed once by
    {!make}. *)

val cube_segments : cube -> segment list
(** The four sides of the cube's footprint. *)

val in_rect : rect -> float -> float -> bool

val over_dropoff : t -> float -> float -> bool
(** Is this floor point inside a drop-off region? *)

val in_cube : cube -> float -> float -> bool
(** Is this point inside the cube's footprint? *)

val disc_hits_cube : cube -> float -> float -> float -> bool
(** [disc_hits_cube c x y r]: does the disc overlap the cube's footprint? *)

val disc_collides : t -> float -> float -> float -> bool
(** Does a disc of radius [r] centred at [(x, y)] overlap a wall or a cube?
    Drop-offs are not obstacles (the robot can drive over them, and fall).
    Only the walls and cubes whose bounding box or circle the disc reaches
    (with a micrometre to spare) are tested exactly: the same answer as
    testing them all, for a few comparisons each (D35). *)

val clearance : t -> float -> float -> float
(** [clearance w x y]: a lower bound of the distance from [(x, y)] to every
    wall and cube footprint (the distance to each wall; to each cube, the
    distance to its centre less half its diagonal); [infinity] in a world
    without either. A disc of radius [r] centred within [clearance w x y -.
    r -. margin] of [(x, y)] collides with nothing: {!Robot} skips
    {!disc_collides} that way (D35). *)

val margin : float
(** The micrometre that the broad phase of {!disc_collides} and the use of
    {!clearance} keep to spare, far above the rounding errors of the
    distances (some 1e-15 m), so that skipping the exact test never changes
    its answer. *)

val ray : t -> float -> float -> float -> max:float -> float option
(** [ray w x y angle ~max]: the distance to the first wall or cube side hit
    by the ray from [(x, y)] in direction [angle], if it is at most [max]. *)

val ray_distance : t -> float -> float -> float -> max:float -> float
(** [ray_distance w x y angle ~max]: the distance {!ray} gives, or [infinity]
    where it gives [None]; the same floats, found without allocating an
    option per side (D35; the proximity sensor casts five rays ten
    times a second). Tested against {!ray} on random rays. *)

val segment_hits_cube : segment -> cube -> bool
(** Does the segment properly cross a side of the cube's footprint, or
    have an end inside it (the boundary included)? *)

val segment_crosses_wall : t -> segment -> bool
(** Does the segment cross one of the extra wall segments (the corridor's
    own walls enclose everything and are never crossed inside it)? *)

val sight_blocked : t -> segment -> except:int -> bool
(** [sight_blocked w s ~except:j]: does [s] hit a cube other than cube [j]
    ({!segment_hits_cube})? The same answer as [Array.exists (fun o -> o !=
    w.cubes.(j) && segment_hits_cube s o) w.cubes] when the cubes are
    distinct records (as {!make} keeps them), from the sides and the yaws'
    sines and cosines computed once (D35; the camera asks it for every
    face in sight, five times a second). Tested against that formula. *)
