type pose = { x : float; y : float; theta : float }

let two_pi = 2. *. Float.pi

let normalise a =
  let a = Float.rem a two_pi in
  let a = if a <= -.Float.pi then a +. two_pi else a in
  if a > Float.pi then a -. two_pi else a

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
