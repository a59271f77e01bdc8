; Four blocks: b1 sits on b0, the others on the table; the goal is the tower b0 on b1
; on b2 on b3 (b3 at the bottom). An example for `sim-host plan` and `sim-host learn`.
(define (problem blocks-4)
  (:domain blocks)
  (:objects b0 b1 b2 b3 - block)
  (:init (hand-empty)
         (on b1 b0) (on-table b0) (on-table b2) (on-table b3)
         (clear b1) (clear b2) (clear b3))
  (:goal (and (on b2 b3) (on b1 b2) (on b0 b1))))
