(** Differential-drive (unicycle) kinematics:
    {v x' = v cos θ,  y' = v sin θ,  θ' = ω v}
    integrated exactly for a command held constant over an interval.

    Frame: x along the corridor, y to its left, θ counter-clockwise from the
    x axis (a left turn has ω > 0). Metres, seconds, radians. *)

type pose = { x : float; y : float; theta : float }

val normalise : float -> float
(** An angle in (-π, π]. *)

val integrate : pose -> v:float -> omega:float -> dt:float -> pose
(** The pose after [dt] seconds at linear speed [v] (m/s) and angular speed
    [omega] (rad/s), in closed form: a straight segment when [omega] is
    (almost) zero, an arc of radius [v /. omega] otherwise. The result's
    heading is normalised. *)

val arc_length : v:float -> dt:float -> float
(** The distance travelled: [|v| dt]. *)

(** {2 The same with sin and cos remembered}

    A physics step needs the sine and cosine of the heading, and the next
    step (and the leading point of the body) needs them again for the same
    angle. A [trig] remembers the last angle asked for and its sine and
    cosine, so that a straight run computes them once, and a turn once a
    step instead of three times (D35). The results are the same floats,
    bit for bit, as calling [sin] and [cos] (tested on random poses). *)

type trig = private { mutable angle : float; mutable sin_a : float; mutable cos_a : float }
(** The last angle asked for ([nan] at first), its sine and its cosine. *)

val trig : unit -> trig
(** A cache that holds no angle yet. *)

val load : trig -> float -> unit
(** [load t a]: afterwards [t.sin_a = sin a] and [t.cos_a = cos a], computed
    only if [a] is not already [t.angle] (the same float, bit for bit). *)

val sin_of : trig -> float -> float
(** [sin_of t a = sin a], computed only if [a] is not the angle [t] holds. *)

val cos_of : trig -> float -> float
(** [cos_of t a = cos a], the same way. *)

val integrate_cached : trig -> pose -> v:float -> omega:float -> dt:float -> pose
(** [integrate_cached t p ~v ~omega ~dt = integrate p ~v ~omega ~dt], bit
    for bit, with the sines and cosines taken from [t] when it holds them. *)
