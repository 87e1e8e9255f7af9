type pose = { x : float; y : float; theta : float }

let two_pi = 2. *. Float.pi

let normalise a =
  let a = Float.rem a two_pi in
  let a = if a <= -.Float.pi then a +. two_pi else a in
  if a > Float.pi then a -. two_pi else a
[@@inline]

let integrate p ~v ~omega ~dt =
  if Float.abs omega < 1e-12 then
    { x = p.x +. v *. dt *. cos p.theta; y = p.y +. v *. dt *. sin p.theta; theta = p.theta }
  else
    let th' = p.theta +. omega *. dt in
    let r = v /. omega in
    { x = p.x +. r *. (sin th' -. sin p.theta);
      y = p.y -. r *. (cos th' -. cos p.theta);
      theta = normalise th' }

let arc_length ~v ~dt = Float.abs v *. dt

(* ------------------------------------------------ the cached sin/cos *)

type trig = { mutable angle : float; mutable sin_a : float; mutable cos_a : float }

let trig () = { angle = nan; sin_a = nan; cos_a = nan }

(* The same float bit for bit (nan never is; 0. and -0. are not the same:
   sin keeps the sign of a zero). *)
let same a b = a = b && (a <> 0. || 1. /. a = 1. /. b) [@@inline]

(* inlined, so that no float is boxed to call it *)
let load t a =
  if not (same t.angle a) then begin
    t.angle <- a; t.sin_a <- sin a; t.cos_a <- cos a
  end [@@inline]

let sin_of t a = load t a; t.sin_a
let cos_of t a = load t a; t.cos_a

let integrate_cached t p ~v ~omega ~dt =
  if Float.abs omega < 1e-12 then begin
    load t p.theta;
    { x = p.x +. v *. dt *. t.cos_a; y = p.y +. v *. dt *. t.sin_a; theta = p.theta }
  end else begin
    load t p.theta;
    let s0 = t.sin_a and c0 = t.cos_a in
    let th' = p.theta +. omega *. dt in
    load t th';
    let r = v /. omega in
    { x = p.x +. r *. (t.sin_a -. s0);
      y = p.y -. r *. (t.cos_a -. c0);
      theta = normalise th' }
  end
