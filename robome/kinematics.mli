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
