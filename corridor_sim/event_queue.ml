type 'a entry = { time : float; seq : int; v : 'a }

type 'a t = { mutable heap : 'a entry array; mutable n : int; mutable next : int }

let create () = { heap = [||]; n = 0; next = 0 }
let is_empty q = q.n = 0
let size q = q.n

let before a b = a.time < b.time || (a.time = b.time && a.seq < b.seq)

let swap h i j = let x = h.(i) in h.(i) <- h.(j); h.(j) <- x

let add q time v =
  let e = { time; seq = q.next; v } in
  q.next <- q.next + 1;
  if q.n = Array.length q.heap then begin
    let h = Array.make (max 16 (2 * q.n)) e in
    Array.blit q.heap 0 h 0 q.n;
    q.heap <- h
  end;
  let h = q.heap in
  h.(q.n) <- e;
  let i = ref q.n in
  q.n <- q.n + 1;
  while !i > 0 && before h.(!i) h.((!i - 1) / 2) do
    swap h !i ((!i - 1) / 2);
    i := (!i - 1) / 2
  done

let pop q =
  if q.n = 0 then None
  else begin
    let h = q.heap in
    let top = h.(0) in
    q.n <- q.n - 1;
    h.(0) <- h.(q.n);
    let i = ref 0 and continue = ref true in
    while !continue do
      let l = 2 * !i + 1 and r = 2 * !i + 2 in
      let m = ref !i in
      if l < q.n && before h.(l) h.(!m) then m := l;
      if r < q.n && before h.(r) h.(!m) then m := r;
      if !m = !i then continue := false else (swap h !i !m; i := !m)
    done;
    Some (top.time, top.v)
  end

let peek_time q = if q.n = 0 then None else Some q.heap.(0).time
