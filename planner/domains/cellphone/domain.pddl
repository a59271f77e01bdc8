; Colledanchise et al. 2019, Section VI: a two-armed robot (ABB YuMi) assembles a cellphone whose parts
; are scattered on a table. Parallel grippers allow no dexterous manipulation: a part
; lying with its front up can only be grasped by the front, which hides the side to be
; assembled; handing it over to the other gripper (a regrasp) exposes it. Only the
; assembling arm mounts parts, and each arm reaches only some parts.
(define (domain cellphone)
  (:requirements :strips :typing :negative-preconditions)
  (:types arm part)
  (:predicates
    (on-table ?p - part)
    (free ?a - arm)
    (holding ?a - arm ?p - part)
    (by-back ?p - part)            ; held by its back: the side to assemble faces out
    (mounted ?p - part)
    (reaches ?a - arm ?p - part)   ; static
    (back-up ?p - part)            ; static: lies with its back up
    (front-up ?p - part)           ; static: lies with its front up
    (assembler ?a - arm)           ; static: the arm that mounts parts
    (other ?a ?b - arm)            ; static
    (base ?p - part)               ; static: goes into the fixture first
    (mounts-on ?p ?q - part))      ; static: p is mounted onto q
  (:action pick-by-back
    :parameters (?a - arm ?p - part)
    :precondition (and (reaches ?a ?p) (back-up ?p) (on-table ?p) (free ?a))
    :effect (and (holding ?a ?p) (by-back ?p) (not (on-table ?p)) (not (free ?a))))
  (:action pick-by-front
    :parameters (?a - arm ?p - part)
    :precondition (and (reaches ?a ?p) (front-up ?p) (on-table ?p) (free ?a))
    :effect (and (holding ?a ?p) (not (on-table ?p)) (not (free ?a))))
  (:action hand-over                 ; the other gripper takes the exposed back
    :parameters (?from ?to - arm ?p - part)
    :precondition (and (other ?from ?to) (holding ?from ?p) (free ?to) (not (by-back ?p)))
    :effect (and (holding ?to ?p) (by-back ?p) (free ?from)
                 (not (holding ?from ?p)) (not (free ?to))))
  (:action place-in-fixture
    :parameters (?a - arm ?p - part)
    :precondition (and (assembler ?a) (base ?p) (holding ?a ?p) (by-back ?p))
    :effect (and (mounted ?p) (free ?a) (not (holding ?a ?p)) (not (by-back ?p))))
  (:action mount
    :parameters (?a - arm ?p ?q - part)
    :precondition (and (assembler ?a) (mounts-on ?p ?q) (mounted ?q) (holding ?a ?p) (by-back ?p))
    :effect (and (mounted ?p) (free ?a) (not (holding ?a ?p)) (not (by-back ?p)))))
