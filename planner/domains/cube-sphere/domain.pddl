; Colledanchise, Almeida, Ögren, ICRA 2019, Fig. 1 and Examples 1-2:
; a mobile manipulator moves a cube onto a goal region while a sphere may block the
; path. Paper notation in the comments.
;
; This file is a contract: the behavior set of every cube/sphere world (symbolic,
; physics, the firmware's plant model) is derived from it. Behavior ids are the
; predicates in declaration order (conditions), then the actions in declaration order;
; a leaf's arguments are object indices in the problem's declaration order.
(define (domain cube-sphere)
  (:requirements :strips :typing :negative-preconditions)
  (:types location - object
          item spot - location)
  (:predicates
    (at ?i - item ?s - spot)        ; o_i = p           (the item lies at the spot)
    (holding ?i - item)             ; h = i
    (hand-empty)                    ; h = ∅
    (near ?l - location)            ; o_r ∈ N_l         (the robot is next to l)
    (path-free ?l - location)       ; τ ⊆ CollFree      (τ the robot's path to l)
    (obstacle ?i - item))           ; static: i may be cleared out of a path
  (:action move-to                  ; MoveTo(p, τ)
    :parameters (?l - location)
    :precondition (path-free ?l)
    :effect (near ?l))
  (:action pick                     ; Pick(i)
    :parameters (?i - item)
    :precondition (and (near ?i) (hand-empty))
    :effect (and (holding ?i) (not (hand-empty))))
  (:action place                    ; Place(i, p)
    :parameters (?i - item ?s - spot)
    :precondition (and (holding ?i) (near ?s))
    :effect (and (at ?i ?s) (hand-empty) (not (holding ?i))))
  (:action drop                     ; Example 2: drop what the hand holds
    :parameters (?i - item)
    :precondition (holding ?i)
    :effect (and (hand-empty) (not (holding ?i))))
  (:action clear-path               ; Example 2: pick the obstacle, put it off the path
    :parameters (?i - item ?l - location)
    :precondition (and (obstacle ?i) (near ?i) (hand-empty))
    :effect (path-free ?l)))
