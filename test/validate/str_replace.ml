(* [replace s a b]: [s] with its first [a] replaced by [b]. *)
let replace s a b =
  match Explore.Str_find.find s a with
  | k -> String.sub s 0 k ^ b ^ String.sub s (k + String.length a) (String.length s - k - String.length a)
  | exception Not_found -> s
