(* gen_values SEED N: values of the interpreter (lib/interp/value.ml) and what
   it makes of them, for the differential test of jsref.values
   (runtime/jade/src/test/java/jsref/values/ValuesTest.java, run by
   scripts/jade-compile-check). One line per case, fields separated by tabs:

     show  ENC  TEXT  LITERAL          Value.to_text and Value.to_literal
     eq    ENC  ENC   0|1              Value.equal

   ENC is a value in prefix form, tokens separated by spaces:
   i:N  d:BITS64  f:BITS32 (hex)  b:0|1  t:HEX (UTF-8 bytes)  a:HEX (aid)  n
   (nothing)  L:K then K values  M:K then K keys and values alternately
   S:HEX:K (schema name, K slots) then K values. TEXT and LITERAL are in hex. *)

module V = Interp.Value

let hex s = String.concat "" (List.map (fun c -> Printf.sprintf "%02x" (Char.code c)) (List.of_seq (String.to_seq s)))

let rec enc (v : V.t) = match v with
  | V.Int i -> Printf.sprintf "i:%d" i
  | V.Double d -> Printf.sprintf "d:%016Lx" (Int64.bits_of_float d)
  | V.Float f -> Printf.sprintf "f:%08lx" (Int32.bits_of_float f)
  | V.Bool b -> if b then "b:1" else "b:0"
  | V.Text s -> "t:" ^ hex s
  | V.Aid s -> "a:" ^ hex s
  | V.Unit -> "n"
  | V.List l -> String.concat " " (Printf.sprintf "L:%d" l.len :: List.map enc (V.list_items l))
  | V.Map m ->
    let bs = V.map_bindings m in
    String.concat " " (Printf.sprintf "M:%d" (List.length bs) :: List.concat_map (fun (k, x) -> [ enc k; enc x ]) bs)
  | V.Schema s ->
    String.concat " " (Printf.sprintf "S:%s:%d" (hex s.sname) (Array.length s.slots)
                       :: List.map (fun (_, r) -> enc !r) (Array.to_list s.slots))
  | _ -> "n"

let special_doubles = [ 0.; -0.; 1.; -1.; 0.1; 0.5; 1.5; 2.5; 100.; 1e7; 9999999.; 1e-3; 9.99e-4; 1e-4; 123456.789;
                        1e21; 1e22; 1e23; 5e-324; 1.7976931348623157e308; Float.infinity; Float.neg_infinity; Float.nan;
                        0.3; 2. /. 3.; 1e16; 12345678.9; 4.35; 100.25; -0.001 ]

let texts = [ ""; "a"; "A7"; "hello world"; "quote\"d"; "back\\slash"; "line\nbreak"; "tab\t"; "cr\r";
              "\001ctl\127"; "caf\xc3\xa9"; "\xf0\x9f\x98\x80"; "x,y"; "{}[]()" ]

let () =
  let seed = int_of_string Sys.argv.(1) and n = int_of_string Sys.argv.(2) in
  let st = Random.State.make [| seed |] in
  let pick l = List.nth l (Random.State.int st (List.length l)) in
  let rnd_double () = match Random.State.int st 4 with
    | 0 -> pick special_doubles
    | 1 -> Int64.float_of_bits (Random.State.int64 st Int64.max_int) *. (if Random.State.bool st then 1. else -1.)
    | 2 -> float_of_int (Random.State.int st 2000 - 1000) /. float_of_int (1 + Random.State.int st 100)
    | _ -> Random.State.float st 1e9 *. (10. ** float_of_int (Random.State.int st 40 - 20)) in
  let rec value depth =
    match Random.State.int st (if depth > 2 then 7 else 10) with
    | 0 -> V.int32 (Random.State.int st 0x3FFFFFFF * (if Random.State.bool st then 1 else -1))
    | 1 -> V.Double (rnd_double ())
    | 2 -> V.Float (V.float32 (rnd_double ()))
    | 3 -> V.Bool (Random.State.bool st)
    | 4 -> V.Text (pick texts)
    | 5 -> V.Aid (pick texts)
    | 6 -> V.Int (Random.State.int st 5)
    | 7 -> V.list_of (List.init (Random.State.int st 4) (fun _ -> value (depth + 1)))
    | 8 ->
      let m = V.map_empty () in
      (match m with
       | V.Map mv -> for _ = 1 to Random.State.int st 4 do V.map_set mv (value (depth + 1)) (value (depth + 1)) done
       | _ -> ());
      m
    | _ ->
      let k = Random.State.int st 3 in
      V.Schema { sname = pick [ "position"; "stop"; "qrCodeRead" ];
                 slots = Array.init k (fun i -> (Printf.sprintf "s%d" i, ref (value (depth + 1)))) } in
  (* small values, often equal to each other *)
  let small () = match Random.State.int st 6 with
    | 0 -> V.Int (Random.State.int st 3)
    | 1 -> V.Double (float_of_int (Random.State.int st 3))
    | 2 -> V.Float (float_of_int (Random.State.int st 3))
    | 3 -> V.list_of [ V.Int (Random.State.int st 2) ]
    | 4 -> V.Schema { sname = "p"; slots = [| ("x", ref (V.Int (Random.State.int st 2))) |] }
    | _ -> V.Schema { sname = "p"; slots = [| ("x", ref (V.Double (float_of_int (Random.State.int st 2)))) |] } in
  List.iter (fun d -> let v = V.Double d in Printf.printf "show\t%s\t%s\t%s\n" (enc v) (hex (V.to_text v)) (hex (V.to_literal v))) special_doubles;
  List.iter (fun d -> let v = V.Float (V.float32 d) in Printf.printf "show\t%s\t%s\t%s\n" (enc v) (hex (V.to_text v)) (hex (V.to_literal v))) special_doubles;
  for _ = 1 to n do
    let v = value 0 in
    Printf.printf "show\t%s\t%s\t%s\n" (enc v) (hex (V.to_text v)) (hex (V.to_literal v));
    let a = small () and b = small () in
    Printf.printf "eq\t%s\t%s\t%d\n" (enc a) (enc b) (if V.equal a b then 1 else 0)
  done
