#!/usr/bin/env bash
# usage: run.sh DATASET N TAG...   (TAG: on | off | mono) -> /tmp/ab/<name>/<tag>_<i>
cd /work/main
DS=$1; N=$2; shift 2
name=$(basename $DS); mkdir -p ${ABROOT:-/tmp/ab}/$name
for i in $(seq 1 $N); do
  for tag in "$@"; do
    out=${ABROOT:-/tmp/ab}/$name/${tag}_$i
    rm -rf $out
    case $tag in
      on)   make eval DATASET=$DS MODE=split OUT=$out > $out.log 2>&1 ;;
      off)  SLAM_CONFIG=/tmp/slam_off.yaml make eval DATASET=$DS MODE=split OUT=$out > $out.log 2>&1 ;;
      mono) make eval DATASET=$DS MODE=monolithic OUT=$out > $out.log 2>&1 ;;
    esac
    echo "$(date +%T) $name $tag $i rc=$?"
  done
done
